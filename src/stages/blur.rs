//! blur: separable box prefilter of the moment planes (horizontal into `scratch`, vertical back).

use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::Result;

pub(crate) struct Blur {
    horizontal: ComputeKernel,
    vertical: ComputeKernel,
}

/// The moment maps a blur reads and writes: `layers` maps of `size`², blurred from `source`
/// through `scratch` (horizontal) into `target` (vertical).
#[derive(Clone, Copy)]
pub(crate) struct BlurMaps<'b> {
    pub(crate) size: u32,
    pub(crate) layers: u32,
    pub(crate) source: &'b wgpu::Buffer,
    pub(crate) scratch: &'b wgpu::Buffer,
    pub(crate) target: &'b wgpu::Buffer,
}

impl Blur {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            horizontal: ComputeKernel::new(ctx, Stage::BLUR, "horizontal")?,
            vertical: ComputeKernel::new(ctx, Stage::BLUR, "vertical")?,
        })
    }

    /// `source` → (horizontal) → `scratch` → (vertical) → `target`; `frame` is the frame uniform
    /// and `map_size` its `map_size` (the dispatch covers the map).
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        frame: &wgpu::Buffer,
        filter: &wgpu::Buffer,
        maps: &BlurMaps,
    ) {
        let BlurMaps {
            size,
            layers,
            source,
            scratch,
            target,
        } = *maps;
        let size3 = [
            groups(size, PIXEL_WORKGROUP[0]),
            groups(size, PIXEL_WORKGROUP[1]),
            layers,
        ];
        for (kernel, from, to) in [
            (&self.horizontal, source, scratch),
            (&self.vertical, scratch, target),
        ] {
            kernel.dispatch(
                ctx,
                enc,
                bind::blur::Blur {
                    frame: frame.as_entire_binding(),
                    settings: filter.as_entire_binding(),
                    source: from.as_entire_binding(),
                    destination: to.as_entire_binding(),
                },
                Dispatch::Direct(size3),
            );
        }
    }
}
