//! What every step of one adaptive frame reads (the level loop in frame.rs, the map store in
//! maps.rs, the steered frame in steer.rs): its own file, so those three import it, not each other.

use super::buffers::AdaptiveBuffers;
use super::Passes;
use crate::methods::{AdaptiveParams, Scope};
use crate::stages::cull::Cull;
use crate::stages::FrameGpu;

/// What every step of one frame reads: the scene's GPU state, the settings, the method's buffers
/// and passes.
pub(super) struct Frame<'a> {
    pub(crate) fg: &'a FrameGpu<'a>,
    pub(crate) p: &'a AdaptiveParams,
    pub(crate) b: &'a AdaptiveBuffers,
    pub(crate) passes: &'a Passes,
    pub(crate) local: bool,
    /// This frame reads back what the decision pictures need (the frame driver's request).
    pub(crate) pictures: bool,
    /// scope = local with culling: the index slots and the indices kept per lattice sample.
    pub(crate) cull: Option<&'a (Cull, wgpu::Buffer)>,
}

impl<'a> Frame<'a> {
    pub(crate) fn new(
        fg: &'a FrameGpu<'a>,
        p: &'a AdaptiveParams,
        b: &'a AdaptiveBuffers,
        passes: &'a Passes,
        cull: Option<&'a (Cull, wgpu::Buffer)>,
        pictures: bool,
    ) -> Self {
        Frame {
            fg,
            p,
            b,
            passes,
            local: p.scope == Scope::Local,
            pictures,
            cull,
        }
    }
}
