//! reconstruct: visibility from the prefiltered statistic at each pixel's place in the map.

use super::{groups, ComputeKernel, Dispatch, FrameGpu, PIXEL_WORKGROUP};
use crate::Result;

pub struct Reconstruct {
    kernel: ComputeKernel,
}

impl Reconstruct {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new(fg.ctx, "reconstruct", "main")? })
    }

    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, filter: &wgpu::Buffer, samples: &wgpu::Buffer, filtered: &wgpu::Buffer) {
        self.kernel.dispatch(
            fg.ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (1, filter.as_entire_binding()),
                (2, samples.as_entire_binding()),
                (3, wgpu::BindingResource::TextureView(&fg.gbuffer.position_view)),
                (4, wgpu::BindingResource::TextureView(&fg.gbuffer.normal_view)),
                (5, filtered.as_entire_binding()),
                (6, fg.visibility.as_entire_binding()),
            ],
            Dispatch::Direct([groups(fg.gbuffer.width, PIXEL_WORKGROUP[0]), groups(fg.gbuffer.height, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
