//! quad_count: low-quality pixels per quad, one atomic counter each.

use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::stages::adaptive_buffers::{Level, LowQuality};
use crate::Result;

pub struct QuadCount {
    kernel: ComputeKernel,
}

impl QuadCount {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new(ctx, Stage::QUAD_COUNT, "main")?,
        })
    }

    /// Counts `low.flags` into `low.per_quad`: over `quads` quads, or as the previous subdivide
    /// sized it (`indirect`: its dispatch arguments).
    pub fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        lv: &Level,
        low: &LowQuality,
        quads: u32,
        indirect: Option<&wgpu::Buffer>,
    ) {
        let words = lv.shape.height * lv.shape.flag_words_per_row;
        self.kernel.dispatch(
            ctx,
            enc,
            bind::quad_count::Main {
                frame: lv.frame.as_entire_binding(),
                level: lv.uniform.as_entire_binding(),
                flags: low.flags.as_entire_binding(),
                quad_counters: low.per_quad.as_entire_binding(),
            },
            match indirect {
                Some(args) => Dispatch::Indirect(args),
                None => Dispatch::Direct([groups(words, LINE_WORKGROUP[0]), quads, 1]),
            },
        );
    }
}
