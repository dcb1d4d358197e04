//! `penumbra failures`: the failure gallery alone, with its own report (the main job runs it too).

use crate::gpu::{AdapterRequest, GpuContext};
use crate::reference::truth;
use crate::studies::compare::{methods_list, run_args::RunArgs, DEFAULT_METHODS};
use crate::studies::failures::{self, GalleryJob};
use crate::studies::flags::OutArgs;
use crate::studies::sequence::MAX_FRAMES;
use anyhow::Result;

/// Gallery image size in the main job: small, so the report's added time stays small on a CPU device.
const MAIN_JOB_RESOLUTION: u32 = 128;
/// Frames of the popping sequence in the main job.
const MAIN_JOB_FRAMES: u32 = 8;

#[derive(clap::Args, Debug, Clone)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/failures")))]
pub struct FailuresArgs {
    /// Methods, comma-separated as in compare (default: the main job's list).
    #[arg(long)]
    methods: Vec<String>,
    /// Width and height of every gallery image.
    #[arg(long, default_value_t = MAIN_JOB_RESOLUTION)]
    resolution: u32,
    /// Frames of the popping sequence (0: none).
    #[arg(long, default_value_t = MAIN_JOB_FRAMES)]
    frames: u32,
    /// Ground truth: `continuous` or `lattice`.
    #[arg(long, default_value = "continuous")]
    reference: String,
    /// M for the continuous reference (M×M samples).
    #[arg(long, default_value_t = 32)]
    samples: u32,
    #[command(flatten)]
    output: OutArgs,
    /// Trace the references without the cache: nothing is read from it or stored in it.
    #[arg(long)]
    no_cache: bool,
}

impl FailuresArgs {
    /// The gallery of the main job: its default methods, against its reference, in `out/failures`.
    pub fn main_job(run: &RunArgs) -> Self {
        FailuresArgs {
            methods: Vec::new(),
            resolution: MAIN_JOB_RESOLUTION,
            frames: MAIN_JOB_FRAMES,
            reference: run.reference.clone(),
            samples: run.samples,
            output: OutArgs {
                out: run.output.out.join("failures"),
            },
            no_cache: false,
        }
    }

    /// The job, every flag checked; the main job's methods when --methods is not given.
    pub fn job(&self) -> Result<GalleryJob> {
        let values = if self.methods.is_empty() {
            vec![DEFAULT_METHODS.to_string()]
        } else {
            self.methods.clone()
        };
        let methods = methods_list::parse_methods(&methods_list::split_specs(&values)?)?;
        if !(16..=2048).contains(&self.resolution) {
            anyhow::bail!("--resolution {}: must be in 16..=2048", self.resolution);
        }
        if self.frames == 1 || self.frames > MAX_FRAMES {
            anyhow::bail!(
                "--frames {}: use 0 (no sequence) or 2..={MAX_FRAMES}",
                self.frames
            );
        }
        Ok(GalleryJob {
            methods,
            resolution: self.resolution,
            frames: self.frames,
            reference: truth::parse_mode(&self.reference, self.samples)?,
            cache: truth::Cache::default_for(self.no_cache),
        })
    }
}

impl crate::studies::Run for FailuresArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

/// Checks the flags, runs, writes the set and its own report.
fn run(args: FailuresArgs, gpu: &AdapterRequest) -> Result<()> {
    let job = args.job()?;
    let ctx = GpuContext::with_request(gpu)?;
    let gallery = failures::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    let html = failures::write(&args.output.out, &gallery)?;
    println!("report: {}", html.display());
    Ok(())
}
