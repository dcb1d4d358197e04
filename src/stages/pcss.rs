//! pcss: blocker search, penumbra width, then PCF of that width, into the visibility buffer.

use super::{groups, ComputeKernel, Dispatch, FrameGpu, PIXEL_WORKGROUP};
use crate::Result;

pub struct Pcss {
    kernel: ComputeKernel,
}

impl Pcss {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new_for(fg.ctx, "pcss", "main", fg.scene.render.maps)? })
    }

    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, filter: &wgpu::Buffer, samples: &wgpu::Buffer, maps: &wgpu::TextureView) {
        self.kernel.dispatch(
            fg.ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (1, filter.as_entire_binding()),
                (2, samples.as_entire_binding()),
                (3, wgpu::BindingResource::TextureView(&fg.gbuffer.position_view)),
                (4, wgpu::BindingResource::TextureView(&fg.gbuffer.normal_view)),
                (5, wgpu::BindingResource::TextureView(maps)),
                (6, fg.visibility.as_entire_binding()),
            ],
            Dispatch::Direct([groups(fg.gbuffer.width, PIXEL_WORKGROUP[0]), groups(fg.gbuffer.height, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
