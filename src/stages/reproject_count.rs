//! reproject_count: c_q(p) for every (pixel, active quad) from the cached masks (dense), or for the
//! compacted (pixel, quad) items from the corners' bits shadow_test `list` cached (scope = local).

use crate::methods::adaptive::buffers::AdaptiveBuffers;
use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP};
use super::FrameGpu;
use crate::Result;

pub struct ReprojectCount {
    dense: ComputeKernel,
    list: ComputeKernel,
    last: ComputeKernel,
    begin: ComputeKernel,
}

impl ReprojectCount {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self {
            dense: ComputeKernel::new(fg.ctx, "reproject_count", "main")?,
            list: ComputeKernel::new(fg.ctx, "reproject_count", "list")?,
            last: ComputeKernel::new(fg.ctx, "reproject_count", "last")?,
            begin: ComputeKernel::new(fg.ctx, "reproject_count", "begin")?,
        })
    }

    pub fn record_dense(
        &self,
        fg: &FrameGpu,
        enc: &mut wgpu::CommandEncoder,
        b: &AdaptiveBuffers,
        level: &wgpu::Buffer,
        quads: &wgpu::Buffer,
    ) {
        let words = b.height * b.words_per_row;
        self.dense.dispatch(
            fg.ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (1, level.as_entire_binding()),
                (2, quads.as_entire_binding()),
                (3, b.masks.as_entire_binding()),
                (5, b.counts.as_entire_binding()),
                (14, b.control.as_entire_binding()),
                (15, b.word_state.as_entire_binding()),
            ],
            Dispatch::Direct([groups(words, LINE_WORKGROUP[0]), 1, 1]),
        );
    }

    /// scope = local: the items appended so far become this level's list (`b.item_total`,
    /// `b.list_args`), read by list, neighbourhood and compact.
    pub fn record_begin(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, level: &wgpu::Buffer) {
        self.begin.dispatch(
            fg.ctx,
            enc,
            &[
                (1, level.as_entire_binding()),
                (13, b.item_total.as_entire_binding()),
                (14, b.control.as_entire_binding()),
                (16, b.list_args.as_entire_binding()),
            ],
            Dispatch::Direct([1, 1, 1]),
        );
    }

    pub fn record_list(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, level: &wgpu::Buffer, quads: &wgpu::Buffer, items: &wgpu::Buffer) {
        self.list.dispatch(
            fg.ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (1, level.as_entire_binding()),
                (2, quads.as_entire_binding()),
                (3, b.masks.as_entire_binding()),
                (10, items.as_entire_binding()),
                (11, b.counts.as_entire_binding()),
                (13, b.item_total.as_entire_binding()),
            ],
            Dispatch::Indirect(&b.list_args),
        );
    }

    /// The last level's items (scope = local): counts go straight into V's integer sums.
    pub fn record_last(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, level: &wgpu::Buffer, quads: &wgpu::Buffer, items: &wgpu::Buffer) {
        self.last.dispatch(
            fg.ctx,
            enc,
            &[
                (1, level.as_entire_binding()),
                (2, quads.as_entire_binding()),
                (3, b.masks.as_entire_binding()),
                (10, items.as_entire_binding()),
                (12, b.visibility_fixed.as_entire_binding()),
                (13, b.item_total.as_entire_binding()),
            ],
            Dispatch::Indirect(&b.list_args),
        );
    }
}
