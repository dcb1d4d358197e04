//! reconstruct: visibility from the prefiltered statistic at each pixel's place in the map.

use crate::gpu::{GpuContext, Stage};
use crate::render::gbuffer::GBuffer;
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::Result;

pub struct Reconstruct {
    kernel: ComputeKernel,
}

impl Reconstruct {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new(ctx, Stage::RECONSTRUCT, "main")? })
    }

    /// `frame`: the frame uniform; writes `visibility` at every G-buffer pixel.
    #[allow(clippy::too_many_arguments)]
    pub fn record(&self, ctx: &GpuContext, enc: &mut wgpu::CommandEncoder, frame: &wgpu::Buffer, gbuffer: &GBuffer, filter: &wgpu::Buffer, samples: &wgpu::Buffer, filtered: &wgpu::Buffer, visibility: &wgpu::Buffer) {
        self.kernel.dispatch(
            ctx,
            enc,
            &[
                ("frame", frame.as_entire_binding()),
                ("settings", filter.as_entire_binding()),
                ("samples", samples.as_entire_binding()),
                ("gbuffer_position", wgpu::BindingResource::TextureView(&gbuffer.position_view)),
                ("gbuffer_normal", wgpu::BindingResource::TextureView(&gbuffer.normal_view)),
                ("moments", filtered.as_entire_binding()),
                ("visibility", visibility.as_entire_binding()),
            ],
            Dispatch::Direct([groups(gbuffer.width, PIXEL_WORKGROUP[0]), groups(gbuffer.height, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
