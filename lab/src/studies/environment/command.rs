//! `penumbra environment`: the environment methods on the panorama scenes (seed 002).

use super::render_sets;
use anyhow::Result;
use penumbra_lab::gpu::{AdapterRequest, GpuContext};
use penumbra_lab::record::output_set;
use penumbra_lab::studies::environment::{self, EnvironmentJob, DEFAULT_METHODS, DEFAULT_SCENES};
use std::path::PathBuf;

#[derive(clap::Args, Debug, Clone)]
pub struct EnvironmentArgs {
    /// Scenes with an [environment], comma-separated.
    #[arg(long, default_value = DEFAULT_SCENES)]
    scenes: String,
    /// Methods, comma-separated as in compare (a method's own parameters joined by `;`).
    #[arg(long, default_value = DEFAULT_METHODS)]
    methods: String,
    /// Timed frames per method (median reported).
    #[arg(long, default_value_t = 3)]
    repeats: u32,
    /// M: the reference takes M×M importance samples per pixel.
    #[arg(long, default_value_t = 32)]
    samples: u32,
    /// `--set key=value` render overrides for every scene (e.g. width=64).
    #[arg(long)]
    set: Vec<String>,
    #[arg(long, default_value = "penumbra-out/environment")]
    out: PathBuf,
    /// Trace the references even when the cache holds them.
    #[arg(long)]
    no_cache: bool,
}

pub fn run(args: EnvironmentArgs, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&args.out)?;
    let overrides = render_sets(&args.set)?;
    let ctx = GpuContext::with_request(gpu)?;
    let job = EnvironmentJob { scenes: args.scenes, methods: args.methods, repeats: args.repeats, samples: args.samples, set: args.set, no_cache: args.no_cache };
    let (outcomes, files) = environment::run(&ctx, &job, &overrides, &|line| eprintln!("{line}"))?;
    let html = environment::write(&args.out, &outcomes, &files)?;
    print!("{}", environment::closing_table(&outcomes));
    println!("adapter: {} ({})", ctx.summary.name, ctx.summary.backend);
    println!("report: {}", html.display());
    Ok(())
}
