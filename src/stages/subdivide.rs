//! subdivide: split decisions, children, new lattice samples, corner levels, dispatch arguments.

use super::{ComputeKernel, Dispatch};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::stages::adaptive_buffers::{Decisions, Level, LowQuality};
use crate::Result;

/// What the split kernel compares at one level (subdivide and its twin).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SplitRule {
    Threshold(u32),
    /// count > share x geometry pixels, compared in f32 on both sides.
    Share(f32),
    Always,
    Never,
}

pub struct Subdivide {
    kernel: ComputeKernel,
}

impl Subdivide {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new(ctx, Stage::SUBDIVIDE, "main")?,
        })
    }

    /// Splits `lv.quads` by `low.per_quad` into `next` (counted in `lv.control`) and updates `out`.
    pub fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        lv: &Level,
        low: &LowQuality,
        next: &wgpu::Buffer,
        out: &Decisions,
    ) {
        let control = lv.control;
        self.kernel.dispatch(
            ctx,
            enc,
            bind::subdivide::Main {
                level: lv.uniform.as_entire_binding(),
                quads: lv.quads.as_entire_binding(),
                quad_counters: low.per_quad.as_entire_binding(),
                next_quads: next.as_entire_binding(),
                control: control.as_entire_binding(),
                lattice_state: out.lattice_state.as_entire_binding(),
                new_samples: out.new_samples.as_entire_binding(),
                sample_level: out.sample_level.as_entire_binding(),
                split_base: out.split_base.as_entire_binding(),
                dispatch_args: out.dispatch_args.as_entire_binding(),
                held: out.held.as_entire_binding(),
            },
            Dispatch::Direct([1, 1, 1]),
        );
    }
}
