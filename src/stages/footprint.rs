//! footprint (cull = on): the culling tiles of a batch of maps, slot z from sample record z of
//! the batch (docs/gpu-frame.md §7), from every geometry pixel (`record`) or from the pixels of
//! the tiles that test the maps (`record_listed`: a `regions` group's).

use super::cull::CullBatch;
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::stages::bind;
use crate::gpu::{readback, GpuContext, Stage};
use crate::render::gbuffer::GBuffer;
use crate::stages::shade::GeometryTiles;
use crate::Result;

pub struct Footprint {
    kernel: ComputeKernel,
    listed: ComputeKernel,
}

impl Footprint {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new(ctx, Stage::FOOTPRINT, "main")?,
            listed: ComputeKernel::new(ctx, Stage::FOOTPRINT, "listed")?,
        })
    }

    /// As `record`, from the pixels of `list`'s tiles alone (one workgroup per listed tile,
    /// dispatched from the list's header). A list in bands is not read this way: `false`, and
    /// nothing recorded (the caller records the whole frame's).
    #[allow(clippy::too_many_arguments)]
    pub fn record_listed(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        frame: &wgpu::Buffer,
        g: &GBuffer,
        batch: &CullBatch,
        slots: u32,
        list: &GeometryTiles,
    ) -> bool {
        let [band] = &list.bands[..] else {
            return false;
        };
        let CullBatch { samples, tiles } = *batch;
        self.listed.dispatch(
            ctx,
            enc,
            bind::footprint::Listed {
                frame: frame.as_entire_binding(),
                samples: samples.as_entire_binding(),
                gbuffer_position: wgpu::BindingResource::TextureView(&g.position_view),
                gbuffer_normal: wgpu::BindingResource::TextureView(&g.normal_view),
                tiles: tiles.as_entire_binding(),
                batch: readback::uniform_buffer(ctx, "footprint batch", &[slots, 0, 0, 0])
                    .as_entire_binding(),
                tile_list: band.tiles(list),
            },
            band.tiles_args(list),
        );
        true
    }

    /// Raises `tiles` (CULL_TILE_WORDS per slot, cleared by the caller) for slots 0..`slots`, whose
    /// sample records are `samples[0..slots]`.
    pub fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        frame: &wgpu::Buffer,
        g: &GBuffer,
        batch: &CullBatch,
        slots: u32,
    ) {
        let CullBatch { samples, tiles } = *batch;
        self.kernel.dispatch(
            ctx,
            enc,
            bind::footprint::Main {
                frame: frame.as_entire_binding(),
                samples: samples.as_entire_binding(),
                gbuffer_position: wgpu::BindingResource::TextureView(&g.position_view),
                gbuffer_normal: wgpu::BindingResource::TextureView(&g.normal_view),
                tiles: tiles.as_entire_binding(),
                batch: readback::uniform_buffer(ctx, "footprint batch", &[slots, 0, 0, 0])
                    .as_entire_binding(),
            },
            Dispatch::Direct([
                groups(g.width, PIXEL_WORKGROUP[0]),
                groups(g.height, PIXEL_WORKGROUP[1]),
                1,
            ]),
        );
    }
}
