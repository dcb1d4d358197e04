//! `penumbra environment`: the environment methods on the panorama scenes (seed 002).

use crate::gpu::{AdapterRequest, GpuContext};
use crate::studies::environment::{self, EnvironmentJob, DEFAULT_METHODS, DEFAULT_SCENES};
use crate::studies::flags::{OutArgs, RepeatsArgs, SetArgs};
use anyhow::Result;

#[derive(clap::Args, Debug, Clone)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/environment")))]
pub struct EnvironmentArgs {
    /// Scenes with an [environment], comma-separated.
    #[arg(long, default_value = DEFAULT_SCENES)]
    scenes: String,
    /// Methods, comma-separated as in compare (a method's own parameters joined by `;`).
    #[arg(long, default_value = DEFAULT_METHODS)]
    methods: String,
    #[command(flatten)]
    repeats: RepeatsArgs,
    /// M: the reference takes M×M importance samples per pixel.
    #[arg(long, default_value_t = 32)]
    samples: u32,
    #[command(flatten)]
    sets: SetArgs,
    #[command(flatten)]
    output: OutArgs,
    /// Trace the references without the cache: nothing is read from it or stored in it.
    #[arg(long)]
    no_cache: bool,
}

impl crate::studies::Run for EnvironmentArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: EnvironmentArgs, gpu: &AdapterRequest) -> Result<()> {
    args.output.checked()?;
    let overrides = args.sets.render()?;
    let ctx = GpuContext::with_request(gpu)?;
    let job = EnvironmentJob {
        scenes: args.scenes,
        methods: args.methods,
        repeats: args.repeats.repeats,
        samples: args.samples,
        set: args.sets.set,
        no_cache: args.no_cache,
    };
    let (outcomes, files) = environment::run(&ctx, &job, &overrides, &|line| eprintln!("{line}"))?;
    let html = environment::write(&args.output.out, &outcomes, &files)?;
    print!("{}", environment::closing_table(&outcomes));
    println!("adapter: {} ({})", ctx.summary.name, ctx.summary.backend);
    println!("report: {}", html.display());
    Ok(())
}
