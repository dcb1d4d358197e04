//! reproject_count: c_q(p) for every (pixel, active quad) from the cached masks (dense), or for the
//! compacted (pixel, quad) items by testing the corner maps (list, scope = local).

use super::buffers::AdaptiveBuffers;
use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP};
use super::FrameGpu;
use crate::Result;

pub struct ReprojectCount {
    dense: ComputeKernel,
    list: ComputeKernel,
}

impl ReprojectCount {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self {
            dense: ComputeKernel::new(fg.ctx, "reproject_count", "main")?,
            list: ComputeKernel::new(fg.ctx, "reproject_count", "list")?,
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

    #[allow(clippy::too_many_arguments)]
    pub fn record_list(
        &self,
        fg: &FrameGpu,
        enc: &mut wgpu::CommandEncoder,
        b: &AdaptiveBuffers,
        level: &wgpu::Buffer,
        quads: &wgpu::Buffer,
        items: &wgpu::Buffer,
        maps: [&wgpu::TextureView; 2],
    ) {
        self.list.dispatch(
            fg.ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (1, level.as_entire_binding()),
                (2, quads.as_entire_binding()),
                (4, wgpu::BindingResource::TextureView(&fg.gbuffer.position_view)),
                (6, b.samples.as_entire_binding()),
                (7, wgpu::BindingResource::TextureView(&fg.gbuffer.normal_view)),
                (8, wgpu::BindingResource::TextureView(maps[0])),
                (9, wgpu::BindingResource::TextureView(maps[1])),
                (10, items.as_entire_binding()),
                (11, b.counts.as_entire_binding()),
                (12, b.masks.as_entire_binding()),
                (13, b.item_total.as_entire_binding()),
                (14, b.control.as_entire_binding()),
            ],
            Dispatch::Indirect(&b.list_args),
        );
    }
}
