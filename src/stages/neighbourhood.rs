//! neighbourhood: the uniform-3x3 low-quality test, one flag bit per (pixel, quad).

use crate::methods::adaptive::buffers::AdaptiveBuffers;
use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP};
use super::FrameGpu;
use crate::Result;

pub struct Neighbourhood {
    dense: ComputeKernel,
    list: ComputeKernel,
}

impl Neighbourhood {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self {
            dense: ComputeKernel::new(fg.ctx, "neighbourhood", "main")?,
            list: ComputeKernel::new(fg.ctx, "neighbourhood", "list")?,
        })
    }

    /// One pass over the flag words; the level uniform's quad count (a GPU copy in the steered
    /// loop) bounds the quads each thread tests.
    pub fn record_dense(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, level: &wgpu::Buffer) {
        let words = b.height * b.flag_words_per_row;
        self.dense.dispatch(
            fg.ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (1, level.as_entire_binding()),
                (2, b.counts.as_entire_binding()),
                (3, b.flags.as_entire_binding()),
                (7, b.word_state.as_entire_binding()),
            ],
            Dispatch::Direct([groups(words, LINE_WORKGROUP[0]), 1, 1]),
        );
    }

    /// scope = local: one item each; also counts each quad's low-quality pixels (`b.quad_counters`,
    /// which the level cleared), so no quad_count pass follows.
    pub fn record_list(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, level: &wgpu::Buffer, items: &wgpu::Buffer) {
        self.list.dispatch(
            fg.ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (1, level.as_entire_binding()),
                (2, b.counts.as_entire_binding()),
                (4, items.as_entire_binding()),
                (5, b.flags.as_entire_binding()),
                (6, b.item_total.as_entire_binding()),
                (7, b.word_state.as_entire_binding()),
                (8, b.quad_counters.as_entire_binding()),
            ],
            Dispatch::Indirect(&b.list_args),
        );
    }
}
