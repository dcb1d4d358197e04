//! ssao: screen-space ambient occlusion from the G-buffer into an AO buffer (and occluded counts).

use super::{groups, ComputeKernel, Dispatch, FrameGpu, PIXEL_WORKGROUP};
use crate::Result;

pub struct Ssao {
    kernel: ComputeKernel,
}

impl Ssao {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new(fg.ctx, "ssao", "main")? })
    }

    #[allow(clippy::too_many_arguments)]
    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, params: &wgpu::Buffer, camera: &wgpu::Buffer, kernel: &wgpu::Buffer, ao: &wgpu::Buffer, occluded: &wgpu::Buffer) {
        self.kernel.dispatch(
            fg.ctx,
            enc,
            &[
                (0, params.as_entire_binding()),
                (1, camera.as_entire_binding()),
                (2, wgpu::BindingResource::TextureView(&fg.gbuffer.position_view)),
                (3, wgpu::BindingResource::TextureView(&fg.gbuffer.normal_view)),
                (4, kernel.as_entire_binding()),
                (5, ao.as_entire_binding()),
                (6, occluded.as_entire_binding()),
            ],
            Dispatch::Direct([groups(fg.gbuffer.width, PIXEL_WORKGROUP[0]), groups(fg.gbuffer.height, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
