//! shade: accumulates weight_i · lit_i(p) over one array's samples into the visibility buffer.

use super::groups;
use crate::gpu::{readback, GpuContext, Stage};
use crate::gpu::structs::GpuSample;
use crate::render::gbuffer::GBuffer;
use crate::Result;

pub const WORKGROUP: [u32; 3] = super::PIXEL_WORKGROUP;
/// Samples per full block (`SHADE_BLOCK` in kernels/shade.wgsl, which unrolls them).
pub const SHADE_BLOCK: u32 = 16;
/// The block sizes, largest first; `block{size}` is the entry point that adds `size` samples.
pub const BLOCK_SIZES: [u32; 5] = [16, 8, 4, 2, 1];

pub struct ShadePass {
    /// One kernel per entry of `BLOCK_SIZES`.
    blocks: Vec<super::ComputeKernel>,
    geometry_tiles: super::ComputeKernel,
    from_masks: super::ComputeKernel,
}

/// Words before the tile indices in a tile list: the blocks' indirect dispatch (count, 1, 1) and a
/// pad (`TILE_LIST_HEADER` in kernels/shade.wgsl).
pub const TILE_LIST_HEADER: usize = 4;
/// Side of a tile: the blocks' workgroup.
pub const TILE: u32 = 8;

/// The 8x8 tiles that hold a geometry pixel, listed on the GPU once per frame with the G-buffer
/// (`geometry_tiles`); shade's and shadow_test's blocks run one workgroup per listed tile, in any
/// order (pixels are independent).
pub struct GeometryTiles {
    pub list: wgpu::Buffer,
    /// The list's header before any tile: count 0, then y = z = 1; copied in every frame.
    header: wgpu::Buffer,
    pub bytes: u64,
}

/// `first .. first + count` as blocks `(start, size)` in sample order: full blocks of SHADE_BLOCK,
/// then the rest's binary decomposition, largest first (25 = 16 + 8 + 1), so no block is short and
/// the additions are a plain loop's, in its order.
pub fn blocks(first: u32, count: u32) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    let mut start = first;
    let end = first + count;
    for size in BLOCK_SIZES {
        while end - start >= size {
            out.push((start, size));
            start += size;
            if size != SHADE_BLOCK {
                break;
            }
        }
    }
    out
}

/// Buffers and views every shade call reads.
pub struct ShadeInputs<'a> {
    pub frame: &'a wgpu::Buffer,
    pub samples: &'a wgpu::Buffer,
    pub weights: &'a wgpu::Buffer,
    pub gbuffer: &'a GBuffer,
    pub visibility: &'a wgpu::Buffer,
}

impl ShadePass {
    /// `maps`: the representation `main` reads (from_masks reads no maps).
    pub fn new(ctx: &GpuContext, maps: crate::scene::MapKind) -> Result<Self> {
        Ok(Self {
            blocks: BLOCK_SIZES
                .iter()
                .map(|size| super::ComputeKernel::new_for(ctx, Stage::SHADE, &format!("block{size}"), maps))
                .collect::<Result<_>>()?,
            geometry_tiles: super::ComputeKernel::new(ctx, Stage::SHADE, "geometry_tiles")?,
            from_masks: super::ComputeKernel::new(ctx, Stage::SHADE, "from_masks")?,
        })
    }

    /// A tile list for images of the G-buffer's size.
    pub fn tile_list(&self, ctx: &GpuContext, gbuffer: &GBuffer) -> GeometryTiles {
        let tiles = groups(gbuffer.width, TILE) * groups(gbuffer.height, TILE);
        let bytes = (TILE_LIST_HEADER as u64 + tiles as u64) * 4;
        let list = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("geometry tiles"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let header = readback::storage_buffer(ctx, "geometry tiles header", &[0u32, 1, 1, 0], wgpu::BufferUsages::COPY_SRC);
        GeometryTiles { list, header, bytes }
    }

    /// Lists this frame's tiles with a geometry pixel (after the G-buffer pass) into `tiles`.
    pub fn record_geometry_tiles(&self, ctx: &GpuContext, encoder: &mut wgpu::CommandEncoder, frame: &wgpu::Buffer, gbuffer: &GBuffer, tiles: &GeometryTiles) {
        encoder.copy_buffer_to_buffer(&tiles.header, 0, &tiles.list, 0, TILE_LIST_HEADER as u64 * 4);
        self.geometry_tiles.dispatch(
            ctx,
            encoder,
            &[
                ("frame", frame.as_entire_binding()),
                ("gbuffer_position", wgpu::BindingResource::TextureView(&gbuffer.position_view)),
                ("tile_list_build", tiles.list.as_entire_binding()),
            ],
            super::Dispatch::Direct([groups(gbuffer.width, TILE), groups(gbuffer.height, TILE), 1]),
        );
    }

    /// Adds samples `first .. first + count` (all in `maps`: a depth array, or a hybrid store's view)
    /// to the visibility buffer.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &ShadeInputs,
        maps: &wgpu::TextureView,
        tiles: &GeometryTiles,
        first: u32,
        count: u32,
    ) {
        let sample_bytes = std::mem::size_of::<GpuSample>() as u64;
        // Blocks in order, each adding to V in sample order: the sum order is the single loop's.
        for (block, block_count) in blocks(first, count) {
            let kernel = &self.blocks[BLOCK_SIZES.iter().position(|&size| size == block_count).expect("a block size")];
            // The block's samples and weights as uniforms (see kernels/shade.wgsl); a smaller block
            // reads only the first `block_count` of each.
            let block_samples = block_uniform(ctx, "shade block samples", SHADE_BLOCK as u64 * sample_bytes);
            let block_weights = block_uniform(ctx, "shade block weights", SHADE_BLOCK as u64 * 4);
            encoder.copy_buffer_to_buffer(inputs.samples, block as u64 * sample_bytes, &block_samples, 0, block_count as u64 * sample_bytes);
            encoder.copy_buffer_to_buffer(inputs.weights, block as u64 * 4, &block_weights, 0, block_count as u64 * 4);
            kernel.dispatch(
                ctx,
                encoder,
                &[
                    ("frame", inputs.frame.as_entire_binding()),
                    ("block_samples", block_samples.as_entire_binding()),
                    ("block_weights", block_weights.as_entire_binding()),
                    ("gbuffer_position", wgpu::BindingResource::TextureView(&inputs.gbuffer.position_view)),
                    ("gbuffer_normal", wgpu::BindingResource::TextureView(&inputs.gbuffer.normal_view)),
                    ("shadow_maps", wgpu::BindingResource::TextureView(maps)),
                    ("visibility", inputs.visibility.as_entire_binding()),
                    ("tile_list", tiles.list.as_entire_binding()),
                ],
                super::Dispatch::Indirect(&tiles.list),
            );
        }
    }

    /// Adaptive, scope = global: V = Σ_k ŵ_k · bit_k(p) from the cached lattice masks.
    #[allow(clippy::too_many_arguments)]
    pub fn record_masks(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::Buffer,
        weights: &wgpu::Buffer,
        gbuffer: &GBuffer,
        masks: &wgpu::Buffer,
        visibility: &wgpu::Buffer,
    ) {
        self.from_masks.dispatch(
            ctx,
            encoder,
            &[
                ("frame", frame.as_entire_binding()),
                ("weights", weights.as_entire_binding()),
                ("gbuffer_position", wgpu::BindingResource::TextureView(&gbuffer.position_view)),
                ("visibility", visibility.as_entire_binding()),
                ("masks", masks.as_entire_binding()),
            ],
            super::Dispatch::Direct([groups(gbuffer.width, WORKGROUP[0]), groups(gbuffer.height, WORKGROUP[1]), 1]),
        );
    }
}

/// A zeroed uniform buffer that a block's copy fills.
fn block_uniform(ctx: &GpuContext, label: &str, bytes: u64) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_cover_the_range_in_sample_order_with_full_blocks() {
        assert_eq!(blocks(0, 25), [(0, 16), (16, 8), (24, 1)]);
        assert_eq!(blocks(5, 15), [(5, 8), (13, 4), (17, 2), (19, 1)]);
        assert_eq!(blocks(0, 1), [(0, 1)]);
        assert_eq!(blocks(3, 0), []);
        for (first, count) in [(0u32, 289u32), (0, 16), (7, 31), (100, 63), (0, 2048)] {
            let b = blocks(first, count);
            // Contiguous and ascending: block i + 1 starts where block i ends, so the additions
            // are a plain loop's over first .. first + count.
            let mut next = first;
            for &(start, size) in &b {
                assert_eq!(start, next, "{first}+{count}: {b:?}");
                assert!(BLOCK_SIZES.contains(&size), "{first}+{count}: size {size}");
                next += size;
            }
            assert_eq!(next, first + count, "{first}+{count}: {b:?}");
            // Full blocks first, then each smaller size at most once, largest first.
            let tail: Vec<u32> = b.iter().map(|&(_, size)| size).skip_while(|&s| s == SHADE_BLOCK).collect();
            assert!(tail.windows(2).all(|w| w[0] > w[1]), "{first}+{count}: {b:?}");
            assert_eq!(b.len() as u32, count / SHADE_BLOCK + (count % SHADE_BLOCK).count_ones());
        }
    }
}
