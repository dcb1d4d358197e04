//! The error columns of the suite (RMSE and FLIP of V against the continuous reference).
//!
//! HOOK(issue 4): the reference tracer and the metrics live on branch `report`. Until they merge,
//! `reference` returns `None`, every error column prints "—" and results.jsonl holds `null`.
//! To wire them: build the `continuous` reference (method.md §5, 32x32 stratified, fixed seed) from
//! `gbuffer` in `reference`, and compute RMSE (geometry pixels only) and FLIP of the shaded image
//! in `errors`. Nothing else in the suite needs to change.

use crate::frame::FrameResult;
use crate::render::gbuffer::GBufferCpu;
use crate::scene::Scene;
use crate::Result;

/// Ground-truth visibility for one scene's G-buffer (shared by both methods: same camera, same pixels).
pub struct Reference {
    pub visibility: Vec<f32>,
    /// How it was made, for the table's header (e.g. "continuous 32x32, CPU BVH").
    pub label: String,
}

#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct ErrorColumns {
    pub rmse: f64,
    pub flip: f64,
}

/// What the table prints while the hook is empty.
pub const PENDING: &str = "pending: reference + metrics (issue 4)";

/// HOOK(issue 4): the continuous reference for this scene, or `None` while it is not merged.
pub fn reference(_scene: &Scene, _gbuffer: &GBufferCpu) -> Result<Option<Reference>> {
    Ok(None)
}

/// HOOK(issue 4): RMSE and FLIP of one frame against the reference.
pub fn errors(_reference: &Reference, _scene: &Scene, _frame: &FrameResult) -> Result<Option<ErrorColumns>> {
    Ok(None)
}
