//! pcf: percentage-closer filtering of one shadow map into the visibility buffer.

use crate::gpu::Stage;
use super::{groups, ComputeKernel, Dispatch, FrameGpu, PIXEL_WORKGROUP};
use crate::Result;

pub struct Pcf {
    kernel: ComputeKernel,
    /// The hardware comparison sampler of `kernel = bilinear` (lit when reference <= stored).
    sampler: wgpu::Sampler,
}

/// The hardware comparison sampler of the bilinear pattern (lit when reference <= stored).
pub fn comparison_sampler(ctx: &crate::gpu::GpuContext) -> wgpu::Sampler {
    ctx.device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("pcf comparison"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        compare: Some(wgpu::CompareFunction::LessEqual),
        ..Default::default()
    })
}

impl Pcf {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new_for(fg.ctx, Stage::PCF, "main", fg.scene.render.maps)?, sampler: comparison_sampler(fg.ctx) })
    }

    /// `samples[0]` is the map's sample; `disk` the tap offsets of the disk kernels.
    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, filter: &wgpu::Buffer, samples: &wgpu::Buffer, maps: &wgpu::TextureView, disk: &wgpu::Buffer) {
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
                ("disk", disk.as_entire_binding()),
                ("visibility", fg.visibility.as_entire_binding()),
                ("compare_sampler", wgpu::BindingResource::Sampler(&self.sampler)),
            ],
            Dispatch::Direct([groups(fg.gbuffer.width, PIXEL_WORKGROUP[0]), groups(fg.gbuffer.height, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
