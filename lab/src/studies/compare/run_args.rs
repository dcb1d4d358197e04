//! The flags compare, sweep and the main job share (and the failure gallery reads).

use crate::studies::flags::{OutArgs, RepeatsArgs, SceneArgs, SetArgs};

/// Settings shared by compare and sweep.
#[derive(clap::Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub repeats: RepeatsArgs,
    /// Ground truth: `continuous`, `lattice`, or `point` / `point:S,T` (the hard shadow from one light point).
    #[arg(long, default_value = "continuous")]
    pub reference: String,
    /// M for the continuous reference (M×M samples).
    #[arg(long, default_value_t = 32)]
    pub samples: u32,
    #[command(flatten)]
    pub sets: SetArgs,
    #[command(flatten)]
    pub output: OutArgs,
    /// Trace the reference without the cache: nothing is read from it or stored in it.
    #[arg(long)]
    pub no_cache: bool,
    /// Certify each method's RMSE from the exact truth at K drawn pixels: "RMSE ≤ U at 95% (K px,
    /// X ms)" beside the measured RMSE (docs/certify.md).
    #[arg(long, value_name = "K")]
    pub certify: Option<usize>,
    /// With --certify: the bound holds with probability 1 − δ (default 0.05).
    #[arg(long, value_name = "δ")]
    pub delta: Option<f64>,
}
