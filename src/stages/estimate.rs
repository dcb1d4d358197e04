//! estimate: adds one range of a fixed sample set's maps to the per-pixel sums of the error
//! estimate (kernels/estimate.wgsl; what they mean: docs/error-estimate.md).

use super::shade::GeometryTiles;
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::kernels::MapAccess;
use crate::gpu::{readback, GpuContext, Stage};
use crate::render::gbuffer::GBuffer;
use crate::Result;

/// Bytes per pixel of the sums (a vec4 of f32).
pub const SUM_BYTES: u64 = 16;

pub struct EstimatePass {
    kernel: ComputeKernel,
}

/// What every range reads and the sums it adds to.
pub struct EstimateInputs<'a> {
    pub frame: &'a wgpu::Buffer,
    pub samples: &'a wgpu::Buffer,
    pub weights: &'a wgpu::Buffer,
    /// Each sample's signed weights in the column and row half-set differences (vec2 of f32).
    pub split: &'a wgpu::Buffer,
    pub gbuffer: &'a GBuffer,
    pub sums: &'a wgpu::Buffer,
}

impl EstimatePass {
    /// `maps`: how the kernel reads the frame's maps (`FrameGpu::map_access`).
    pub fn new(ctx: &GpuContext, maps: MapAccess) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new_for(ctx, Stage::ESTIMATE, "main", maps)? })
    }

    /// Adds samples `first .. first + count` (all in `maps`) to the sums. The sums are bound
    /// whole, so the frame must be one band (`check_bands`).
    #[allow(clippy::too_many_arguments)]
    pub fn record(&self, ctx: &GpuContext, enc: &mut wgpu::CommandEncoder, inputs: &EstimateInputs, maps: &wgpu::TextureView, first: u32, count: u32) {
        let range = readback::uniform_buffer(ctx, "estimate range", &[first, count, 0, 0]);
        self.kernel.dispatch(
            ctx,
            enc,
            &[
                ("frame", inputs.frame.as_entire_binding()),
                ("range", range.as_entire_binding()),
                ("samples", inputs.samples.as_entire_binding()),
                ("weights", inputs.weights.as_entire_binding()),
                ("split", inputs.split.as_entire_binding()),
                ("gbuffer_position", wgpu::BindingResource::TextureView(&inputs.gbuffer.position_view)),
                ("gbuffer_normal", wgpu::BindingResource::TextureView(&inputs.gbuffer.normal_view)),
                ("shadow_maps", wgpu::BindingResource::TextureView(maps)),
                ("sums", inputs.sums.as_entire_binding()),
            ],
            Dispatch::Direct([groups(inputs.gbuffer.width, PIXEL_WORKGROUP[0]), groups(inputs.gbuffer.height, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}

/// The sums are bound whole: a frame whose V is split into bands of rows is refused.
pub fn check_bands(tiles: &GeometryTiles, width: u32, height: u32) -> Result<()> {
    if tiles.bands.len() > 1 {
        return Err(crate::Error::Param(format!(
            "estimate = on binds its per-pixel sums whole, and a {width}×{height} frame is split into {} bands; use a smaller resolution",
            tiles.bands.len()
        )));
    }
    Ok(())
}
