//! pcss: blocker search, penumbra width, then PCF of that width, into the visibility buffer.

use crate::gpu::Stage;
use super::{groups, ComputeKernel, Dispatch, FrameGpu, PIXEL_WORKGROUP};
use crate::Result;

pub struct Pcss {
    kernel: ComputeKernel,
}

impl Pcss {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new_for(fg.ctx, Stage::PCSS, "main", fg.scene.render.maps)? })
    }

    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, filter: &wgpu::Buffer, samples: &wgpu::Buffer, maps: &wgpu::TextureView) {
        self.kernel.dispatch(
            fg.ctx,
            enc,
            &[
                ("frame", fg.frame_buffer.as_entire_binding()),
                ("settings", filter.as_entire_binding()),
                ("samples", samples.as_entire_binding()),
                ("gbuffer_position", wgpu::BindingResource::TextureView(&fg.gbuffer.position_view)),
                ("gbuffer_normal", wgpu::BindingResource::TextureView(&fg.gbuffer.normal_view)),
                ("shadow_maps", wgpu::BindingResource::TextureView(maps)),
                ("visibility", fg.visibility.as_entire_binding()),
            ],
            Dispatch::Direct([groups(fg.gbuffer.width, PIXEL_WORKGROUP[0]), groups(fg.gbuffer.height, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
