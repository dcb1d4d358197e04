//! cascades: the sun's cascaded shadow maps into the visibility buffer, with the cascade each
//! pixel took.

use super::pcf::comparison_sampler;
use super::shade::Screen;
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::kernels::MapAccess;
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::Result;

/// `chosen` on background pixels (`NO_CASCADE` in the kernel).
pub const NO_CASCADE: u32 = u32::MAX;
/// `GpuCascades.filter`.
pub const FILTER_HARD: u32 = 0;
pub const FILTER_PCF: u32 = 1;

pub(crate) struct Cascades {
    kernel: ComputeKernel,
    sampler: wgpu::Sampler,
}

/// What the kernel reads besides the frame's buffers.
pub(crate) struct CascadeInputs<'a> {
    /// pcf's filter uniform and tap offsets (read when `filter = pcf`).
    pub(crate) filter: &'a wgpu::Buffer,
    pub(crate) disk: &'a wgpu::Buffer,
    /// One sample per cascade, `samples[i].layer = i`.
    pub(crate) samples: &'a wgpu::Buffer,
    pub(crate) maps: &'a wgpu::TextureView,
    /// The `GpuCascades` uniform.
    pub(crate) cascades: &'a wgpu::Buffer,
    /// One u32 per pixel: the cascade taken, `NO_CASCADE` on background.
    pub(crate) chosen: &'a wgpu::Buffer,
}

impl Cascades {
    pub(crate) fn new(ctx: &GpuContext, maps: MapAccess) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new_for(ctx, Stage::CASCADES, "main", maps)?,
            sampler: comparison_sampler(ctx),
        })
    }

    /// Writes `visibility` and `chosen` at every pixel of the G-buffer (V at geometry pixels).
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        screen: &Screen,
        inputs: &CascadeInputs,
    ) {
        let Screen {
            frame,
            gbuffer,
            tiles,
            visibility,
        } = *screen;
        for band in &tiles.bands {
            self.kernel.dispatch(
                ctx,
                enc,
                bind::cascades::Main {
                    frame: band.frame(frame).as_entire_binding(),
                    settings: inputs.filter.as_entire_binding(),
                    samples: inputs.samples.as_entire_binding(),
                    gbuffer_position: wgpu::BindingResource::TextureView(&gbuffer.position_view),
                    gbuffer_normal: wgpu::BindingResource::TextureView(&gbuffer.normal_view),
                    shadow_maps: wgpu::BindingResource::TextureView(inputs.maps),
                    disk: inputs.disk.as_entire_binding(),
                    visibility: band.pixels(tiles, visibility, gbuffer.width, 4),
                    compare_sampler: wgpu::BindingResource::Sampler(&self.sampler),
                    cascades: inputs.cascades.as_entire_binding(),
                    chosen: band.pixels(tiles, inputs.chosen, gbuffer.width, 4),
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
