//! moments: the centre map's depths as the statistic a filtered method prefilters.

use crate::gpu::stages::bind;
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::kernels::MapAccess;
use crate::gpu::{GpuContext, Stage};
use crate::Result;

pub struct Moments {
    kernel: ComputeKernel,
}

impl Moments {
    /// `raster`: how the raster's layers are read (`Raster::raster_access`).
    pub fn new(ctx: &GpuContext, raster: MapAccess) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new_for(ctx, Stage::MOMENTS, "main", raster)? })
    }

    /// `frame`: the frame uniform; `map_size`: its `map_size` (the dispatch covers the map).
    #[allow(clippy::too_many_arguments)]
    pub fn record(&self, ctx: &GpuContext, enc: &mut wgpu::CommandEncoder, frame: &wgpu::Buffer, map_size: u32, filter: &wgpu::Buffer, samples: &wgpu::Buffer, maps: &wgpu::TextureView, out: &wgpu::Buffer) {
        let size = map_size;
        self.kernel.dispatch(
            ctx,
            enc,
            bind::moments::Main {
                frame: frame.as_entire_binding(),
                settings: filter.as_entire_binding(),
                samples: samples.as_entire_binding(),
                shadow_maps: wgpu::BindingResource::TextureView(maps),
                moments: out.as_entire_binding(),
            },
            Dispatch::Direct([groups(size, PIXEL_WORKGROUP[0]), groups(size, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
