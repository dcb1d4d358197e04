//! estimate: adds one range of a fixed sample set's maps to the per-pixel sums of the error
//! estimate (kernels/estimate.wgsl; what they mean: docs/error-estimate.md). Blocks of samples in
//! sample order, as shade adds them (`shade::blocks`), one workgroup per geometry tile.

use super::shade::{block_uniform, blocks, GeometryTiles, BLOCK_SIZES, SHADE_BLOCK};
use super::ComputeKernel;
use crate::gpu::kernels::MapAccess;
use crate::gpu::stages::bind;
use crate::gpu::structs::GpuSample;
use crate::gpu::{GpuContext, Stage};
use crate::render::gbuffer::GBuffer;
use crate::Result;

/// One pixel's sums: V's half-set differences (columns, rows), Q, B, then the half-set
/// differences of Q (columns, rows) and of B (kernels/estimate.wgsl `EstimateSums`).
pub(crate) type Sums = [f32; 8];

/// Bytes per pixel of the sums (two vec4 of f32).
pub(crate) const SUM_BYTES: u64 = 32;

pub(crate) struct EstimatePass {
    /// One kernel per entry of `shade::BLOCK_SIZES`.
    blocks: Vec<ComputeKernel>,
}

/// What every range reads and the sums it adds to.
pub(crate) struct EstimateInputs<'a> {
    pub(crate) frame: &'a wgpu::Buffer,
    pub(crate) samples: &'a wgpu::Buffer,
    pub(crate) weights: &'a wgpu::Buffer,
    /// Each sample's signed weights in the column and row half-set differences (vec2 of f32).
    pub(crate) split: &'a wgpu::Buffer,
    pub(crate) gbuffer: &'a GBuffer,
    pub(crate) tiles: &'a GeometryTiles,
    pub(crate) sums: &'a wgpu::Buffer,
}

impl EstimatePass {
    /// `maps`: how the kernel reads the frame's maps (`FrameGpu::map_access`).
    pub(crate) fn new(ctx: &GpuContext, maps: MapAccess) -> Result<Self> {
        Ok(Self {
            blocks: BLOCK_SIZES
                .iter()
                .map(|size| {
                    ComputeKernel::new_for(ctx, Stage::ESTIMATE, &format!("block{size}"), maps)
                })
                .collect::<Result<_>>()?,
        })
    }

    /// Adds samples `first .. first + count` (all in `maps`) to the sums. The sums are bound
    /// whole, so the frame must be one band (`check_bands`).
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        inputs: &EstimateInputs,
        maps: &wgpu::TextureView,
        first: u32,
        count: u32,
    ) {
        let sample_bytes = std::mem::size_of::<GpuSample>() as u64;
        let band = &inputs.tiles.bands[0];
        for (block, size) in blocks(first, count) {
            let kernel = &self.blocks[BLOCK_SIZES
                .iter()
                .position(|&s| s == size)
                .expect("a block size")];
            // The block's samples, weights and splits as uniforms read at constant offsets.
            let samples = block_uniform(
                ctx,
                "estimate block samples",
                SHADE_BLOCK as u64 * sample_bytes,
            );
            let weights = block_uniform(ctx, "estimate block weights", SHADE_BLOCK as u64 * 4);
            let split = block_uniform(ctx, "estimate block split", SHADE_BLOCK as u64 * 8);
            enc.copy_buffer_to_buffer(
                inputs.samples,
                block as u64 * sample_bytes,
                &samples,
                0,
                size as u64 * sample_bytes,
            );
            enc.copy_buffer_to_buffer(
                inputs.weights,
                block as u64 * 4,
                &weights,
                0,
                size as u64 * 4,
            );
            enc.copy_buffer_to_buffer(inputs.split, block as u64 * 8, &split, 0, size as u64 * 8);
            kernel.dispatch(
                ctx,
                enc,
                bind::estimate::Block {
                    frame: inputs.frame.as_entire_binding(),
                    block_samples: samples.as_entire_binding(),
                    block_weights: weights.as_entire_binding(),
                    block_split: split.as_entire_binding(),
                    gbuffer_position: wgpu::BindingResource::TextureView(
                        &inputs.gbuffer.position_view,
                    ),
                    gbuffer_normal: wgpu::BindingResource::TextureView(&inputs.gbuffer.normal_view),
                    shadow_maps: wgpu::BindingResource::TextureView(maps),
                    sums: inputs.sums.as_entire_binding(),
                    tile_list: band.tiles(inputs.tiles),
                },
                band.tiles_args(inputs.tiles),
            );
        }
    }
}

/// The sums are bound whole: a frame whose V is split into bands of rows is refused.
pub(crate) fn check_bands(tiles: &GeometryTiles, width: u32, height: u32) -> Result<()> {
    if tiles.bands.len() > 1 {
        return Err(crate::Error::Param(format!(
            "estimate = on binds its per-pixel sums whole, and a {width}×{height} frame is split into {} bands; use a smaller resolution",
            tiles.bands.len()
        )));
    }
    Ok(())
}
