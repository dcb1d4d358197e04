//! subdivide: split decisions, children, new lattice samples, corner levels, dispatch arguments.

use crate::methods::adaptive::buffers::AdaptiveBuffers;
use super::{ComputeKernel, Dispatch};
use super::FrameGpu;
use crate::Result;

pub struct Subdivide {
    kernel: ComputeKernel,
}

impl Subdivide {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new(fg.ctx, "subdivide", "main")? })
    }

    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, level: &wgpu::Buffer, quads: &wgpu::Buffer, next: &wgpu::Buffer) {
        self.kernel.dispatch(
            fg.ctx,
            enc,
            &[
                (0, level.as_entire_binding()),
                (1, quads.as_entire_binding()),
                (2, b.quad_counters.as_entire_binding()),
                (3, next.as_entire_binding()),
                (4, b.control.as_entire_binding()),
                (5, b.lattice_state.as_entire_binding()),
                (6, b.new_samples.as_entire_binding()),
                (7, b.sample_level.as_entire_binding()),
                (8, b.split_base.as_entire_binding()),
                (9, b.dispatch_args.as_entire_binding()),
            ],
            Dispatch::Direct([1, 1, 1]),
        );
    }
}
