//! `penumbra certify-study`: the certified bound's coverage and sharpness on scenes × methods ×
//! proxies × K × draws, and the stretch fitted on the fitting half (docs/certify.md §4).

use crate::gpu::{AdapterRequest, GpuContext};
use crate::record::run_files;
use crate::reference::truth;
use crate::scene::Scene;
use crate::studies::certify::{self, Job};
use crate::studies::flags::{OutArgs, SetArgs};
use crate::studies::lists::listed_once;
use anyhow::Result;

#[derive(clap::Args)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/certify-study")))]
pub struct CertifyStudyArgs {
    /// Scenes (built-in names or TOML paths), comma-separated; default: the fixed split's 15.
    #[arg(long, value_delimiter = ',', value_parser = crate::studies::flags::utf8())]
    scenes: Vec<String>,
    /// Methods, comma-separated as `compare --methods` takes them; default: the main job's.
    #[arg(long, default_value = crate::studies::compare::MAIN_JOB_METHODS)]
    methods: Vec<String>,
    /// K, the pixels drawn per bound, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = certify::DEFAULT_PIXELS)]
    pixels: Vec<usize>,
    /// Draws per (scene, method, proxy, K).
    #[arg(long, default_value_t = certify::DEFAULT_DRAWS)]
    draws: u32,
    /// δ: each bound holds with probability 1 − δ.
    #[arg(long, default_value_t = crate::certify::DEFAULT_DELTA)]
    delta: f64,
    #[command(flatten)]
    sets: SetArgs,
    #[command(flatten)]
    output: OutArgs,
    /// Trace the reference even when the cache holds it.
    #[arg(long)]
    no_cache: bool,
}

impl crate::studies::Run for CertifyStudyArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: CertifyStudyArgs, gpu: &AdapterRequest) -> Result<()> {
    args.output.checked()?;
    let sets = args.sets.render()?;
    if !(args.delta > 0.0 && args.delta < 1.0) {
        anyhow::bail!(
            "--delta {}: outside (0, 1): each bound holds with probability 1 − delta",
            args.delta
        );
    }
    if args.draws == 0 || args.draws > 1000 {
        anyhow::bail!("--draws {}: give 1..=1000", args.draws);
    }
    if let Some(k) = args.pixels.iter().find(|&&k| k == 0) {
        anyhow::bail!("--pixels {k}: draw at least one pixel");
    }
    listed_once("--pixels", args.pixels.iter().map(|k| (k.to_string(), *k)))?;
    let methods = crate::studies::compare::methods_list::split_specs(&args.methods)?;
    crate::studies::compare::methods_list::parse_methods(&methods)?;
    let scenes: Vec<String> = if args.scenes.is_empty() {
        crate::studies::calibration::SPLIT
            .iter()
            .map(|(s, _)| s.to_string())
            .collect()
    } else {
        listed_once("--scenes", args.scenes.iter().map(|s| (s, s.trim())))?;
        args.scenes.clone()
    };
    for name in &scenes {
        if let Some(why) = crate::certify::truth::unsupported(&Scene::load(name, &sets)?) {
            anyhow::bail!("--scenes {name}: {why}");
        }
    }
    let ctx = GpuContext::with_request(gpu)?;
    let cache = truth::Cache::default_for(args.no_cache);
    let job = Job {
        methods: &methods,
        pixels: &args.pixels,
        draws: args.draws,
        delta: args.delta,
        mode: truth::parse_mode("continuous", 32)?,
    };
    let mut rows = Vec::new();
    for name in &scenes {
        rows.extend(certify::run_scene(&ctx, name, &sets, &job, &cache, &|l| {
            eprintln!("{l}")
        })?);
    }
    let files = certify::files(&rows)?;
    run_files::write_files(&args.output.out, &files)?;
    print!("{}", String::from_utf8_lossy(&files[1].1));
    println!("rows:    {}", args.output.out.join("certify.csv").display());
    Ok(())
}

/// `penumbra certify-promise`: `auto:target=T` beside each committed frontier's oracle.
#[derive(clap::Args)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/certify-promise")))]
pub struct CertifyPromiseArgs {
    /// Folders of `penumbra frontier --budget …` runs (each with its frontier.jsonl), comma-separated.
    #[arg(long, value_delimiter = ',', required = true, value_parser = crate::studies::flags::utf8())]
    frontiers: Vec<String>,
    #[command(flatten)]
    repeats: crate::studies::flags::RepeatsArgs,
    #[command(flatten)]
    output: OutArgs,
}

impl crate::studies::Run for CertifyPromiseArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        self.output.checked()?;
        let repeats = self.repeats.checked()?;
        listed_once("--frontiers", self.frontiers.iter().map(|s| (s, s.trim())))?;
        let mut rows = 0;
        for dir in &self.frontiers {
            rows += certify::promise::check(std::path::Path::new(dir))
                .map_err(|e| anyhow::anyhow!("--frontiers {dir}: {e}"))?;
        }
        eprintln!("{rows} auto rows in {} frontiers", self.frontiers.len());
        let ctx = GpuContext::with_request(gpu)?;
        let mut all = Vec::new();
        for dir in &self.frontiers {
            all.extend(certify::promise::run_frontier(
                &ctx,
                std::path::Path::new(dir),
                repeats,
                &|l| eprintln!("{l}"),
            )?);
        }
        let md = certify::promise::markdown(&all);
        run_files::write_files(
            &self.output.out,
            &[
                (
                    "promise.csv".to_string(),
                    certify::promise::csv(&all).into_bytes(),
                ),
                ("promise.md".to_string(), md.clone().into_bytes()),
            ],
        )?;
        print!("{md}");
        println!("rows: {}", self.output.out.join("promise.csv").display());
        Ok(())
    }
}
