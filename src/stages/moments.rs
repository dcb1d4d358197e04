//! moments: the centre map's depths as the statistic a filtered method prefilters.

use crate::gpu::{GpuContext, Stage};
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::Result;

pub struct Moments {
    kernel: ComputeKernel,
}

impl Moments {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new(ctx, Stage::MOMENTS, "main")? })
    }

    /// `frame`: the frame uniform; `map_size`: its `map_size` (the dispatch covers the map).
    #[allow(clippy::too_many_arguments)]
    pub fn record(&self, ctx: &GpuContext, enc: &mut wgpu::CommandEncoder, frame: &wgpu::Buffer, map_size: u32, filter: &wgpu::Buffer, samples: &wgpu::Buffer, maps: &wgpu::TextureView, out: &wgpu::Buffer) {
        let size = map_size;
        self.kernel.dispatch(
            ctx,
            enc,
            &[
                ("frame", frame.as_entire_binding()),
                ("settings", filter.as_entire_binding()),
                ("samples", samples.as_entire_binding()),
                ("shadow_maps", wgpu::BindingResource::TextureView(maps)),
                ("moments", out.as_entire_binding()),
            ],
            Dispatch::Direct([groups(size, PIXEL_WORKGROUP[0]), groups(size, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
