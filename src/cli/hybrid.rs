//! `penumbra hybrid`: hybrid-resolution shadow maps (seed 003) against plain maps.

use super::render_sets;
use anyhow::{Context, Result};
use penumbra::gpu::{AdapterRequest, GpuContext};
use penumbra::record::{output_set, run_files};
use penumbra::reference::truth;
use penumbra::scene::Scene;
use penumbra::studies::compare::methods_list;
use penumbra::studies::hybrid::{self, parse_maps};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct HybridArgs {
    /// Built-in scene name or path to a scene TOML file.
    #[arg(long, default_value = "default", value_parser = crate::cli::utf8())]
    scene: String,
    /// Square screen size in pixels.
    #[arg(long, allow_negative_numbers = true, default_value_t = 256)]
    resolution: u32,
    /// Plain map sizes of the hard-shadow part, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "512,1024,2048,4096")]
    plain: Vec<String>,
    /// Hybrid maps of the hard-shadow part as BASE/LEVELS, comma-separated (2048/2 is 2048 → 512).
    #[arg(long, value_delimiter = ',', default_value = "1024/1,2048/1,2048/2,4096/2")]
    hybrid: Vec<String>,
    /// Merge tolerance in 16-bit depth units (the seed's 0.25).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.25)]
    eps: f32,
    /// Timed hard-shadow frames per configuration after a warm-up and a stages-mode frame.
    #[arg(long, allow_negative_numbers = true, default_value_t = 3)]
    repeats: u32,
    /// Multi-map methods (comma-separated; empty for none), e.g. `regular:n=17,adaptive:preset=balanced`.
    #[arg(long, value_delimiter = ',', default_value = "")]
    multi: Vec<String>,
    /// The multi-map methods' hybrid maps, BASE/LEVELS.
    #[arg(long, default_value = "2048/2")]
    multi_hybrid: String,
    /// Plain sizes the multi-map methods also run with (the size of equal memory is added).
    #[arg(long, value_delimiter = ',', default_value = "512")]
    multi_plain: Vec<String>,
    /// Timed multi-map frames per configuration after one stages-mode frame (no warm-up: slow scenes).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    multi_repeats: u32,
    /// Override a render setting, e.g. `--set shadow_map_budget_mib=1024`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    #[arg(long, default_value = "penumbra-out/hybrid")]
    out: PathBuf,
}

pub fn run(args: HybridArgs, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&args.out)?;
    if !(8..=4096).contains(&args.resolution) {
        anyhow::bail!("--resolution: {} is not in 8..=4096", args.resolution);
    }
    if !(args.eps.is_finite() && args.eps >= 0.0) {
        anyhow::bail!("--eps: {} must be a finite number >= 0", args.eps);
    }
    for (flag, n) in [("--repeats", args.repeats), ("--multi-repeats", args.multi_repeats)] {
        if n == 0 || n > 1000 {
            anyhow::bail!("{flag} must be in 1..=1000, got {n}");
        }
    }
    let mut sets = render_sets(&args.set)?;
    sets.push(("resolution".into(), args.resolution.to_string()));
    let scene = Scene::load(&args.scene, &sets)?;
    let mut hard = Vec::new();
    for p in args.plain.iter().filter(|s| !s.trim().is_empty()) {
        hard.push(parse_maps(p, false).with_context(|| "--plain")?);
    }
    for h in args.hybrid.iter().filter(|s| !s.trim().is_empty()) {
        hard.push(parse_maps(h, true).with_context(|| "--hybrid")?);
    }
    let multi_specs: Vec<String> = args.multi.iter().filter(|s| !s.trim().is_empty()).cloned().collect();
    let multi = methods_list::parse_methods(&multi_specs)?;
    let multi_plain = args
        .multi_plain
        .iter()
        .filter(|s| !s.trim().is_empty())
        .map(|p| match parse_maps(p, false) {
            Ok(hybrid::Maps::Plain(size)) => Ok(size),
            Ok(_) => unreachable!("plain sizes parse as plain maps"),
            Err(e) => Err(anyhow::Error::from(e).context("--multi-plain")),
        })
        .collect::<Result<Vec<u32>>>()?;
    let job = hybrid::HybridJob {
        scene,
        hard,
        eps: args.eps,
        repeats: args.repeats,
        multi,
        multi_hybrid: parse_maps(&args.multi_hybrid, true).with_context(|| "--multi-hybrid")?,
        multi_plain,
        multi_repeats: args.multi_repeats,
        cache: truth::Cache::default_for(false),
    };
    let ctx = GpuContext::with_request(gpu)?;
    let outcome = hybrid::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    run_files::write_files(&args.out, &outcome.files)?;
    print!("{}", hybrid::files::markdown(&outcome.rows));
    println!("adapter: {} ({}); wall clock", ctx.summary.name, ctx.summary.backend);
    println!("study: {}", args.out.join("hybrid.md").display());
    Ok(())
}
