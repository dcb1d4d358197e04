//! The `failures` command's flags, and the gallery as part of the main job's report.

use super::{Gallery, GalleryJob};
use crate::studies::compare::methods_list;
use crate::gpu::{AdapterRequest, GpuContext};
use crate::studies::sequence::report::{append_to_page, write_set};
use crate::reference::truth;
use crate::{Result};
use std::path::{Path, PathBuf};

/// Gallery image size in the main job: small, so the report's added time stays small on a CPU device.
pub const MAIN_JOB_RESOLUTION: u32 = 128;
/// Frames of the popping sequence in the main job.
pub const MAIN_JOB_FRAMES: u32 = 8;

#[derive(clap::Args, Debug, Clone)]
pub struct FailuresArgs {
    /// Methods, comma-separated as in compare (default: the main job's list).
    #[arg(long)]
    pub methods: Vec<String>,
    /// Width and height of every gallery image.
    #[arg(long, default_value_t = MAIN_JOB_RESOLUTION)]
    pub resolution: u32,
    /// Frames of the popping sequence (0: none).
    #[arg(long, default_value_t = MAIN_JOB_FRAMES)]
    pub frames: u32,
    /// Ground truth: `continuous` or `lattice`.
    #[arg(long, default_value = "continuous")]
    pub reference: String,
    /// M for the continuous reference (M×M samples).
    #[arg(long, default_value_t = 32)]
    pub samples: u32,
    /// Output folder.
    #[arg(long, default_value = "penumbra-out/failures")]
    pub out: PathBuf,
    /// Trace the references even when the cache holds them.
    #[arg(long)]
    pub no_cache: bool,
}

impl FailuresArgs {
    /// The job, every flag checked; `default_methods` when --methods is not given.
    pub fn job(&self, default_methods: &str) -> Result<GalleryJob> {
        let values = if self.methods.is_empty() { vec![default_methods.to_string()] } else { self.methods.clone() };
        let methods = methods_list::parse_methods(&methods_list::split_specs(&values)?)?;
        if !(16..=2048).contains(&self.resolution) {
            return Err(crate::Error::Param(format!("--resolution {}: must be in 16..=2048", self.resolution)));
        }
        if self.frames == 1 || self.frames > crate::studies::sequence::MAX_FRAMES {
            return Err(crate::Error::Param(format!("--frames {}: use 0 (no sequence) or 2..={}", self.frames, crate::studies::sequence::MAX_FRAMES)));
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

/// `penumbra failures`: checks the flags, runs, writes the set and its own report.
pub fn run(args: &FailuresArgs, default_methods: &str, gpu: &AdapterRequest, log: &dyn Fn(&str)) -> Result<(Gallery, PathBuf)> {
    let job = args.job(default_methods)?;
    let ctx = GpuContext::with_request(gpu)?;
    let gallery = super::run(&ctx, &job, log)?;
    let html = super::write(&args.out, &gallery)?;
    Ok((gallery, html))
}

/// The main job: the gallery's files under `out/failures/`, its sections in `out/report.html`.
pub fn attach(out: &Path, gallery: &Gallery) -> Result<()> {
    write_set(&out.join("failures"), &gallery.files)?;
    append_to_page(&out.join("report.html"), &super::sections(gallery)?)
}
