//! reconstruct: visibility from the prefiltered statistic at each pixel's place in the map.

use super::shade::Screen;
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::Result;

pub(crate) struct Reconstruct {
    kernel: ComputeKernel,
}

impl Reconstruct {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new(ctx, Stage::RECONSTRUCT, "main")?,
        })
    }

    /// `frame`: the frame uniform; writes `visibility` at every G-buffer pixel.
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        screen: &Screen,
        filter: &wgpu::Buffer,
        samples: &wgpu::Buffer,
        filtered: &wgpu::Buffer,
    ) {
        let Screen {
            frame,
            gbuffer,
            tiles,
            visibility,
        } = *screen;
        // A band of rows per dispatch (`tiles.bands`; one band unless V passes one binding).
        for band in &tiles.bands {
            self.kernel.dispatch(
                ctx,
                enc,
                bind::reconstruct::Main {
                    frame: band.frame(frame).as_entire_binding(),
                    settings: filter.as_entire_binding(),
                    samples: samples.as_entire_binding(),
                    gbuffer_position: wgpu::BindingResource::TextureView(&gbuffer.position_view),
                    gbuffer_normal: wgpu::BindingResource::TextureView(&gbuffer.normal_view),
                    moments: filtered.as_entire_binding(),
                    visibility: band.pixels(tiles, visibility, gbuffer.width, 4),
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
