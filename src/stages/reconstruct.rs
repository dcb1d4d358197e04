//! reconstruct: visibility from the prefiltered statistic at each pixel's place in the map.

use crate::gpu::Stage;
use super::{groups, ComputeKernel, Dispatch, FrameGpu, PIXEL_WORKGROUP};
use crate::Result;

pub struct Reconstruct {
    kernel: ComputeKernel,
}

impl Reconstruct {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new(fg.ctx, Stage::RECONSTRUCT, "main")? })
    }

    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, filter: &wgpu::Buffer, samples: &wgpu::Buffer, filtered: &wgpu::Buffer) {
        self.kernel.dispatch(
            fg.ctx,
            enc,
            &[
                ("frame", fg.frame_buffer.as_entire_binding()),
                ("settings", filter.as_entire_binding()),
                ("samples", samples.as_entire_binding()),
                ("gbuffer_position", wgpu::BindingResource::TextureView(&fg.gbuffer.position_view)),
                ("gbuffer_normal", wgpu::BindingResource::TextureView(&fg.gbuffer.normal_view)),
                ("moments", filtered.as_entire_binding()),
                ("visibility", fg.visibility.as_entire_binding()),
            ],
            Dispatch::Direct([groups(fg.gbuffer.width, PIXEL_WORKGROUP[0]), groups(fg.gbuffer.height, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
