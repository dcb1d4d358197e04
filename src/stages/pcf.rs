//! pcf: percentage-closer filtering of one shadow map into the visibility buffer.

use super::shade::{MapFilter, Screen};
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::kernels::MapAccess;
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::Result;

pub(crate) struct Pcf {
    kernel: ComputeKernel,
    /// The hardware comparison sampler of `kernel = bilinear` (lit when reference <= stored).
    sampler: wgpu::Sampler,
}

/// The hardware comparison sampler of the bilinear pattern (lit when reference <= stored).
pub(crate) fn comparison_sampler(ctx: &GpuContext) -> wgpu::Sampler {
    ctx.device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("pcf comparison"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        compare: Some(wgpu::CompareFunction::LessEqual),
        ..Default::default()
    })
}

impl Pcf {
    /// `maps`: how the kernel reads the frame's maps (`FrameGpu::map_access`).
    pub(crate) fn new(ctx: &GpuContext, maps: MapAccess) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new_for(ctx, Stage::PCF, "main", maps)?,
            sampler: comparison_sampler(ctx),
        })
    }

    /// `frame`: the frame uniform; `samples[0]` is the map's sample; `disk` the tap offsets of the
    /// disk kernels. Writes `visibility` at every G-buffer pixel.
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        screen: &Screen,
        map: &MapFilter,
        disk: &wgpu::Buffer,
    ) {
        let (
            Screen {
                frame,
                gbuffer,
                tiles,
                visibility,
            },
            MapFilter {
                filter,
                samples,
                maps,
            },
        ) = (*screen, *map);
        // A band of rows per dispatch (`tiles.bands`; one band unless V passes one binding).
        for band in &tiles.bands {
            self.kernel.dispatch(
                ctx,
                enc,
                bind::pcf::Main {
                    frame: band.frame(frame).as_entire_binding(),
                    settings: filter.as_entire_binding(),
                    samples: samples.as_entire_binding(),
                    gbuffer_position: wgpu::BindingResource::TextureView(&gbuffer.position_view),
                    gbuffer_normal: wgpu::BindingResource::TextureView(&gbuffer.normal_view),
                    shadow_maps: wgpu::BindingResource::TextureView(maps),
                    disk: disk.as_entire_binding(),
                    visibility: band.pixels(tiles, visibility, gbuffer.width, 4),
                    compare_sampler: wgpu::BindingResource::Sampler(&self.sampler),
                },
                Dispatch::Direct([
                    groups(gbuffer.width, PIXEL_WORKGROUP[0]),
                    groups(band.rows, PIXEL_WORKGROUP[1]),
                    1,
                ]),
            );
        }
    }
}
