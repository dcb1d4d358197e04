//! pcss: blocker search, penumbra width, then PCF of that width, into the visibility buffer.

use super::shade::{MapFilter, Screen};
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::kernels::MapAccess;
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::Result;

pub(crate) struct Pcss {
    kernel: ComputeKernel,
}

impl Pcss {
    /// `maps`: how the kernel reads the frame's maps (`FrameGpu::map_access`).
    pub(crate) fn new(ctx: &GpuContext, maps: MapAccess) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new_for(ctx, Stage::PCSS, "main", maps)?,
        })
    }

    /// `frame`: the frame uniform; writes `visibility` at every G-buffer pixel.
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        screen: &Screen,
        map: &MapFilter,
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
                bind::pcss::Main {
                    frame: band.frame(frame).as_entire_binding(),
                    settings: filter.as_entire_binding(),
                    samples: samples.as_entire_binding(),
                    gbuffer_position: wgpu::BindingResource::TextureView(&gbuffer.position_view),
                    gbuffer_normal: wgpu::BindingResource::TextureView(&gbuffer.normal_view),
                    shadow_maps: wgpu::BindingResource::TextureView(maps),
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
