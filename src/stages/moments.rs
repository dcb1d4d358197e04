//! moments: the centre map's depths as the statistic a filtered method prefilters.

use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::kernels::MapAccess;
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::Result;

pub(crate) struct Moments {
    kernel: ComputeKernel,
}

impl Moments {
    /// `raster`: how the raster's layers are read (`Raster::raster_access`).
    pub(crate) fn new(ctx: &GpuContext, raster: MapAccess) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new_for(ctx, Stage::MOMENTS, "main", raster)?,
        })
    }

    /// `frame`: the frame uniform; `map_size`: its `map_size` (the dispatch covers the map).
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        bindings: bind::moments::Main,
        map_size: u32,
    ) {
        self.kernel.dispatch(
            ctx,
            enc,
            bindings,
            Dispatch::Direct([
                groups(map_size, PIXEL_WORKGROUP[0]),
                groups(map_size, PIXEL_WORKGROUP[1]),
                1,
            ]),
        );
    }
}
