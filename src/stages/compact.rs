//! compact (scope = local): next level's items, the uniform shares of unrefined quads, scissor
//! rectangles; `seed` and `resolve` start the item list and finish V (reproject_count `begin`
//! starts each level's list).

use crate::methods::adaptive::buffers::AdaptiveBuffers;
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use super::FrameGpu;
use crate::Result;

pub struct Compact {
    main: ComputeKernel,
    /// `main` that also grows the scissor rectangles and culling tiles (scissor or cull on).
    main_rects: ComputeKernel,
    seed: ComputeKernel,
    resolve: ComputeKernel,
}

impl Compact {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        let k = |e| ComputeKernel::new(fg.ctx, "compact", e);
        Ok(Self { main: k("main")?, main_rects: k("main_rects")?, seed: k("seed")?, resolve: k("resolve")? })
    }

    fn pixels(b: &AdaptiveBuffers) -> Dispatch<'static> {
        Dispatch::Direct([groups(b.width, PIXEL_WORKGROUP[0]), groups(b.height, PIXEL_WORKGROUP[1]), 1])
    }

    pub fn record_seed(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, level: &wgpu::Buffer, items: &wgpu::Buffer) {
        self.seed.dispatch(
            fg.ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (1, level.as_entire_binding()),
                (5, items.as_entire_binding()),
                (6, b.control.as_entire_binding()),
                (11, wgpu::BindingResource::TextureView(&fg.gbuffer.position_view)),
            ],
            Self::pixels(b),
        );
    }

    #[allow(clippy::too_many_arguments)]
    pub fn record_main(
        &self,
        fg: &FrameGpu,
        enc: &mut wgpu::CommandEncoder,
        b: &AdaptiveBuffers,
        level: &wgpu::Buffer,
        items: &wgpu::Buffer,
        next_items: &wgpu::Buffer,
        next_quads: &wgpu::Buffer,
        grow_rects: bool,
    ) {
        // Both entry points share the item code, so both take every binding.
        let kernel = if grow_rects { &self.main_rects } else { &self.main };
        kernel.dispatch(
            fg.ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (1, level.as_entire_binding()),
                (2, items.as_entire_binding()),
                (3, b.counts.as_entire_binding()),
                (4, b.split_base.as_entire_binding()),
                (5, next_items.as_entire_binding()),
                (6, b.control.as_entire_binding()),
                (7, b.visibility_fixed.as_entire_binding()),
                (8, next_quads.as_entire_binding()),
                (9, b.samples.as_entire_binding()),
                (10, b.rects.as_entire_binding()),
                (11, wgpu::BindingResource::TextureView(&fg.gbuffer.position_view)),
                (12, wgpu::BindingResource::TextureView(&fg.gbuffer.normal_view)),
                (14, b.item_total.as_entire_binding()),
                (16, b.probes.as_entire_binding()),
                (17, b.tiles.as_entire_binding()),
            ],
            Dispatch::Indirect(&b.list_args),
        );
    }

    pub fn record_resolve(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, level: &wgpu::Buffer) {
        self.resolve.dispatch(
            fg.ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (1, level.as_entire_binding()),
                (7, b.visibility_fixed.as_entire_binding()),
                (13, fg.visibility.as_entire_binding()),
            ],
            Self::pixels(b),
        );
    }
}
