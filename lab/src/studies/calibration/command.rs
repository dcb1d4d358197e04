//! `penumbra calibrate`: the calibrated estimate's factors fitted on the fitting half of
//! `penumbra estimate`'s pairs and read on every half (docs/budget.md).

use super::{self as study, Pair};
use crate::gpu::AdapterRequest;
use crate::methods::calibration::{self, Class};
use crate::record::{output_set, run_files};
use crate::scene::Scene;
use crate::studies::estimate::EstimateLine;
use crate::studies::Run;
use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct CalibrateArgs {
    /// `estimate.jsonl` files of `penumbra estimate`, comma-separated.
    #[arg(long, value_delimiter = ',', required = true)]
    estimates: Vec<PathBuf>,
    /// Scenes the pairs name that are not built in (TOML paths, comma-separated): each pair's class
    /// comes from its scene's light.
    #[arg(long, value_delimiter = ',', value_parser = crate::studies::flags::utf8())]
    scenes: Vec<String>,
    /// Report the engine's factors (the default) or a refit on these pairs' fitting half.
    #[arg(long)]
    refit: bool,
    #[arg(long, default_value = "penumbra-out/calibrate")]
    out: PathBuf,
}

impl Run for CalibrateArgs {
    fn run(self, _gpu: &AdapterRequest) -> Result<()> {
        run(self)
    }
}

fn run(args: CalibrateArgs) -> Result<()> {
    output_set::check(&args.out)?;
    // The same file twice would count every pair twice; two spellings of one file too.
    crate::studies::lists::listed_once(
        "--estimates",
        args.estimates.iter().map(|p| {
            (
                p.display().to_string(),
                p.canonicalize().unwrap_or_else(|_| p.clone()),
            )
        }),
    )?;
    output_set::check_inputs(
        &args.out,
        &args
            .estimates
            .iter()
            .map(|p| ("--estimates", p.as_path()))
            .collect::<Vec<_>>(),
    )?;
    let mut extra = Vec::new();
    for path in &args.scenes {
        extra.push(Scene::load(path, &[])?);
    }
    let mut pairs = Vec::new();
    let mut failed = 0;
    for file in &args.estimates {
        let text = crate::scene::input_file::read_text(
            file,
            crate::scene::input_file::TEXT_CAP,
            "the 256 MiB cap on rows files",
        )
        .map_err(|e| anyhow::anyhow!("--estimates {}: cannot read: {e}", file.display()))?;
        let mut rows = 0;
        for (i, line) in text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty())
        {
            let l: EstimateLine = serde_json::from_str(line).map_err(|e| {
                anyhow::anyhow!("--estimates {}: line {}: {e}", file.display(), i + 1)
            })?;
            rows += 1;
            if let Some(why) = l.check() {
                anyhow::bail!("--estimates {}: line {}: {why}", file.display(), i + 1);
            }
            if l.failed.is_some() {
                failed += 1;
                continue;
            }
            let kind = match extra.iter().find(|s| s.name == l.core.scene) {
                Some(s) => s.emitter.kind(),
                None => Scene::load(&l.core.scene, &[]).map_err(|_| anyhow::anyhow!("--estimates {}: line {}: scene `{}` is not built in; name its TOML in --scenes", file.display(), i + 1, l.core.scene))?.emitter.kind(),
            };
            pairs.push(Pair::from_line(&l, Class::of(kind)));
        }
        if rows == 0 {
            anyhow::bail!("--estimates {}: holds no estimate row (give an estimate.jsonl of `penumbra estimate`)", file.display());
        }
    }
    if pairs.is_empty() {
        anyhow::bail!(
            "--estimates {}: all {failed} rows are failed settings: no pair to calibrate",
            args.estimates
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(",")
        );
    }
    let engine = (
        calibration::factors(Class::Plane),
        calibration::factors(Class::Cube),
    );
    let factors = if args.refit {
        study::fit(&pairs).ok_or_else(|| {
            anyhow::anyhow!("--refit: no factors up to 4 cover 95% of the fitting half's pairs")
        })?
    } else {
        engine
    };
    run_files::write_files(&args.out, &study::files(&pairs, factors)?)?;
    let md = study::markdown(&pairs, factors);
    print!("{md}");
    if args.refit && factors != engine {
        println!("\nthe refit differs from the engine's factors (src/methods/calibration.rs): plane {:?}, ball {:?}", engine.0, engine.1);
    }
    println!(
        "\ncalibration: {}",
        args.out.join("calibration.md").display()
    );
    Ok(())
}
