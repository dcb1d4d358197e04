//! Timing one method the way architecture.md asks: one warm-up frame, one frame in stages mode
//! (a wait after every stage, so each stage's wall time is known), then `repeats` frames in frame
//! mode (only the waits the method needs) whose median is the figure quoted.

use crate::frame::{self, FrameOptions, FrameResult};
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::scene::Scene;
use crate::timing::TimingMode;
use crate::Result;
use std::collections::BTreeMap;


pub struct Measured {
    /// The last frame-mode run: its visibility is what the metrics judge.
    pub frame: FrameResult,
    pub totals_ms: Vec<f64>,
    pub median_ms: f64,
    pub min_ms: f64,
    pub max_ms: f64,
    /// Wall time per stage from the stages-mode run, setup stages removed.
    pub stages_ms: BTreeMap<String, f64>,
    pub setup_ms: Option<f64>,
}

/// Median of a non-empty list (mean of the middle two for an even count).
pub fn median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) }
}

pub fn measure(ctx: &GpuContext, scene: &Scene, method: &Method, repeats: u32) -> Result<Measured> {
    // No decision pictures: their read-backs would be timed, and compare does not use them.
    // One renderer: pipelines and buffers are built once (the warm-up's setup) and reused.
    let mut renderer = frame::Renderer::new(ctx, scene, method)?;
    let mut run = |mode| renderer.frame(FrameOptions { mode, pictures: false, capture: false });
    run(TimingMode::Frame)?; // warm-up: driver caches, allocator, pipeline build
    let staged = run(TimingMode::Stages)?;
    let mut totals_ms = Vec::new();
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let r = run(TimingMode::Frame)?;
        totals_ms.push(r.total_ms);
        last = Some(r);
    }
    let frame = last.expect("at least one repeat");
    let mut stages_ms = staged.stages_ms.clone();
    // `setup` (per-frame zero fills; the build was the warm-up's) runs before the frame's clock starts.
    let setup = stages_ms.remove("setup");
    stages_ms.remove("upload");
    stages_ms.remove("build");
    Ok(Measured {
        median_ms: median(&totals_ms),
        min_ms: totals_ms.iter().copied().fold(f64::INFINITY, f64::min),
        max_ms: totals_ms.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        totals_ms,
        stages_ms,
        setup_ms: setup,
        frame,
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn median_odd_and_even() {
        assert_eq!(super::median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(super::median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(super::median(&[7.0]), 7.0);
    }
}
