//! The flags compare, sweep and the main job share (and the failure gallery reads).

use std::path::PathBuf;

/// Settings shared by compare and sweep.
#[derive(clap::Args)]
pub struct RunArgs {
    /// Built-in scene name or path to a scene TOML file.
    #[arg(long, default_value = "default", value_parser = crate::cli::utf8())]
    pub scene: String,
    /// Timed frames per method after one warm-up (and one stages-mode frame); the median is quoted.
    #[arg(long, default_value_t = 3)]
    pub repeats: u32,
    /// Ground truth: `continuous`, `lattice`, or `point` / `point:S,T` (the hard shadow from one light point).
    #[arg(long, default_value = "continuous")]
    pub reference: String,
    /// M for the continuous reference (M×M samples).
    #[arg(long, default_value_t = 32)]
    pub samples: u32,
    /// Override a render setting, e.g. `--set resolution=256` (method parameters go in --methods).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output folder.
    #[arg(long, default_value = "penumbra-out")]
    pub out: PathBuf,
    /// Trace the reference even when the cache holds it.
    #[arg(long)]
    pub no_cache: bool,
}
