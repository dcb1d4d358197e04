//! quad_count: low-quality pixels per quad, one atomic counter each.

use crate::methods::adaptive::buffers::AdaptiveBuffers;
use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP};
use super::FrameGpu;
use crate::Result;

pub struct QuadCount {
    kernel: ComputeKernel,
}

impl QuadCount {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new(fg.ctx, "quad_count", "main")? })
    }

    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, level: &wgpu::Buffer, quads: u32, indirect: bool) {
        let words = b.height * b.flag_words_per_row;
        self.kernel.dispatch(
            fg.ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (1, level.as_entire_binding()),
                (2, b.flags.as_entire_binding()),
                (3, b.quad_counters.as_entire_binding()),
            ],
            if indirect { Dispatch::Indirect(&b.dispatch_args) } else { Dispatch::Direct([groups(words, LINE_WORKGROUP[0]), quads, 1]) },
        );
    }
}
