//! shadow_test: caches lit_k(p) of newly rendered maps as bits of each pixel's lattice mask.

use super::buffers::AdaptiveBuffers;
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use super::FrameGpu;
use crate::gpu::readback;
use crate::layout::GpuLevel;
use crate::Result;

pub struct ShadowTest {
    kernel: ComputeKernel,
}

impl ShadowTest {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new_for(fg.ctx, "shadow_test", "main", fg.scene.render.maps)? })
    }

    /// Tests lattice samples `ks` (ascending), whose maps are layers of `maps` (or slots of a
    /// hybrid store's view); skips those not requested this frame.
    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, maps: &wgpu::TextureView, ks: &[u32]) {
        let ctx = fg.ctx;
        let level = readback::uniform_buffer(ctx, "level", &GpuLevel { work_count: ks.len() as u32, ..Default::default() });
        let list = readback::storage_buffer(ctx, "test list", ks, wgpu::BufferUsages::empty());
        self.dispatch(fg, enc, b, maps, &level, &list);
    }

    /// Tests the samples the last subdivide requested (`b.new_samples`, as many as it appended):
    /// the GPU-steered loop, when a level's maps fit one array.
    pub fn record_requested(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, maps: &wgpu::TextureView) {
        let level = readback::uniform_buffer(fg.ctx, "level", &GpuLevel { requested: 1, ..Default::default() });
        self.dispatch(fg, enc, b, maps, &level, &b.new_samples);
    }

    fn dispatch(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, maps: &wgpu::TextureView, level: &wgpu::Buffer, list: &wgpu::Buffer) {
        let ctx = fg.ctx;
        self.kernel.dispatch(
            ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (1, level.as_entire_binding()),
                (2, b.samples.as_entire_binding()),
                (3, list.as_entire_binding()),
                (4, wgpu::BindingResource::TextureView(&fg.gbuffer.position_view)),
                (5, wgpu::BindingResource::TextureView(&fg.gbuffer.normal_view)),
                (6, wgpu::BindingResource::TextureView(maps)),
                (7, b.masks.as_entire_binding()),
                (8, b.lattice_state.as_entire_binding()),
                (9, b.control.as_entire_binding()),
            ],
            Dispatch::Direct([groups(b.width, PIXEL_WORKGROUP[0]), groups(b.height, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
