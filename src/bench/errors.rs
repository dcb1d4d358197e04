//! The error columns of the suite: RMSE of V and FLIP of the shaded image against the continuous
//! reference (method.md §5: 32x32 stratified jitter, fixed seed, CPU BVH), cached on disk.

use crate::frame::FrameResult;
use crate::ground_truth::{self, Cache};
use crate::metrics;
use crate::output;
use crate::reference::ReferenceMode;
use crate::render::gbuffer::GBufferCpu;
use crate::scene::Scene;
use crate::Result;

/// Ground-truth visibility for one scene's G-buffer (shared by both methods: same camera, same pixels).
pub struct Reference {
    pub visibility: Vec<f32>,
    /// How it was made, for the table's header (e.g. "continuous 32x32, CPU BVH").
    pub label: String,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct ErrorColumns {
    pub rmse: f64,
    pub flip: f64,
    /// Every metric (the report's accuracy table and charts).
    #[serde(skip)]
    pub metrics: metrics::Metrics,
}

/// What the table prints when a column has no value.
pub const PENDING: &str = "no reference";

/// The continuous reference for this scene (traced once, then read from the cache).
pub fn reference(scene: &Scene, gbuffer: &GBufferCpu) -> Result<Option<Reference>> {
    let mode = ReferenceMode::DEFAULT_CONTINUOUS;
    let image = ground_truth::compute(scene, gbuffer, mode, &Cache::default_for(false))?;
    Ok(Some(Reference { visibility: image.values, label: format!("{}, CPU BVH", ground_truth::mode_label(&mode)) }))
}

/// RMSE (geometry pixels) and mean FLIP of one frame against the reference.
pub fn errors(reference: &Reference, scene: &Scene, frame: &FrameResult) -> Result<Option<ErrorColumns>> {
    let g = &frame.gbuffer;
    let mask: Vec<bool> = (0..g.position.len()).map(|i| g.is_geometry(i)).collect();
    let shaded = output::shaded_image(&frame.visibility, g, scene);
    let shaded_reference = output::shaded_image(&reference.visibility, g, scene);
    let m = metrics::compute(&frame.visibility, &reference.visibility, &mask, &shaded, &shaded_reference, g.width, g.height)?;
    Ok(Some(ErrorColumns { rmse: m.rmse, flip: m.flip_mean, metrics: m }))
}
