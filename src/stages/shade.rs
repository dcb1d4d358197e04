//! shade: accumulates weight_i · lit_i(p) over one array's samples into the visibility buffer.

use super::groups;
use crate::gpu::stages::bind;
use crate::gpu::structs::GpuSample;
use crate::gpu::{readback, GpuContext, Stage};
use crate::render::gbuffer::GBuffer;
use crate::Result;

pub(crate) const WORKGROUP: [u32; 3] = super::PIXEL_WORKGROUP;
/// Samples per full block (`SHADE_BLOCK` in kernels/shade.wgsl, which unrolls them).
pub const SHADE_BLOCK: u32 = 16;
/// The block sizes, largest first; `block{size}` is the entry point that adds `size` samples.
pub(crate) const BLOCK_SIZES: [u32; 5] = [16, 8, 4, 2, 1];

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
pub(crate) const TILE: u32 = 8;

/// The 8x8 tiles that hold a geometry pixel, listed on the GPU once per frame with the G-buffer
/// (`geometry_tiles`); shade's and shadow_test's blocks run one workgroup per listed tile, in any
/// order (pixels are independent). With bands, each band's tiles are listed in its own section.
pub struct GeometryTiles {
    pub(crate) list: wgpu::Buffer,
    /// The list's header before any tile: count 0, then y = z = 1; copied in every frame.
    header: wgpu::Buffer,
    pub(crate) bytes: u64,
    /// Rows per band (0: one band) and the bands, top to bottom.
    pub(crate) band_rows: u32,
    pub(crate) bands: Vec<Band>,
}

/// A band of rows. A per-pixel storage buffer larger than one binding may be (V at 5,793² and up
/// on lavapipe's 128 MiB, adaptive's lattice masks at 1,832²) is bound a band at a time: the
/// passes dispatch once per band, with the band's frame uniform (its `band_first_row`), its range
/// of the buffer and its section of the tile list. Each pixel is computed as without bands, so V
/// is the same bit for bit (lab/tests/large_frames.rs).
pub(crate) struct Band {
    pub(crate) first_row: u32,
    pub(crate) rows: u32,
    /// The frame uniform with this band's first row; None for a single band (the frame's own).
    frame: Option<wgpu::Buffer>,
    tiles_offset: u64,
    tiles_bytes: u64,
}

impl Band {
    /// The frame uniform this band's dispatches bind.
    pub(crate) fn frame<'b>(&'b self, whole: &'b wgpu::Buffer) -> &'b wgpu::Buffer {
        self.frame.as_ref().unwrap_or(whole)
    }

    /// This band's section of the tile list (header and tiles).
    pub(crate) fn tiles<'b>(&self, tiles: &'b GeometryTiles) -> wgpu::BindingResource<'b> {
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &tiles.list,
            offset: self.tiles_offset,
            size: wgpu::BufferSize::new(self.tiles_bytes),
        })
    }

    /// The indirect dispatch arguments of this band's tiles: (count, 1, 1) at its section's start.
    pub(crate) fn tiles_args<'b>(&self, tiles: &'b GeometryTiles) -> super::Dispatch<'b> {
        super::Dispatch::IndirectAt(&tiles.list, self.tiles_offset)
    }

    /// This band's rows of a per-pixel buffer of `bytes_per_pixel` (the whole buffer for a single band).
    pub(crate) fn pixels<'b>(
        &self,
        tiles: &GeometryTiles,
        buffer: &'b wgpu::Buffer,
        width: u32,
        bytes_per_pixel: u64,
    ) -> wgpu::BindingResource<'b> {
        if tiles.bands.len() == 1 {
            return buffer.as_entire_binding();
        }
        let row = width as u64 * bytes_per_pixel;
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer,
            offset: self.first_row as u64 * row,
            size: wgpu::BufferSize::new(self.rows as u64 * row),
        })
    }
}

impl GeometryTiles {
    /// A tile list in `bytes` of `list` from byte `offset` (256-aligned), one band of `height`
    /// rows: a subset of the geometry tiles that another pass listed (the regions' classes).
    pub fn section(list: &wgpu::Buffer, offset: u64, bytes: u64, height: u32) -> GeometryTiles {
        GeometryTiles {
            list: list.clone(),
            header: list.clone(),
            bytes,
            band_rows: 0,
            bands: vec![Band {
                first_row: 0,
                rows: height,
                frame: None,
                tiles_offset: offset,
                tiles_bytes: bytes,
            }],
        }
    }

    /// Sets the frame uniform's band fields and writes each band's copy of it: the main frame
    /// buffer (made from `frame` after this) lists the tiles by band.
    pub(crate) fn stamp(&self, ctx: &GpuContext, frame: &mut crate::gpu::structs::GpuFrame) {
        frame.band_rows = self.band_rows;
        frame.bands = self.bands.len() as u32;
        frame.tile_section_words = (self.bytes / 4 / self.bands.len() as u64) as u32;
        frame.band_first_row = 0;
        for band in &self.bands {
            if let Some(buffer) = &band.frame {
                let copy = crate::gpu::structs::GpuFrame {
                    band_first_row: band.first_row,
                    ..*frame
                };
                ctx.queue.write_buffer(buffer, 0, bytemuck::bytes_of(&copy));
            }
        }
    }
}

/// Rows per band for per-pixel buffers of `row_bytes` bytes per row under `max_binding`: whole
/// tiles high and aligned for binding offsets of every per-pixel buffer (a multiple of 4 bytes per
/// pixel); 0 when the image fits one binding. None when not even one band's minimum fits.
pub(crate) fn band_rows(
    width: u32,
    height: u32,
    row_bytes: u64,
    max_binding: u64,
    offset_alignment: u32,
) -> Option<u32> {
    if row_bytes * height as u64 <= max_binding {
        return Some(0);
    }
    let granule = band_granule(width, offset_alignment);
    let rows = (max_binding / row_bytes) as u32 / granule * granule;
    (rows > 0).then_some(rows)
}

/// The least band height: a multiple of the tile side whose rows of 4 bytes per pixel start at an
/// aligned offset.
pub(crate) fn band_granule(width: u32, offset_alignment: u32) -> u32 {
    let mut rows = TILE;
    while (rows as u64 * width as u64 * 4) % offset_alignment.max(1) as u64 != 0 {
        rows += TILE;
    }
    rows
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
/// The screen a per-pixel pass covers and writes V over: the frame uniform, the G-buffer, its
/// geometry tiles (whose bands split a dispatch where V passes one storage binding) and V.
#[derive(Clone, Copy)]
pub(crate) struct Screen<'b> {
    pub(crate) frame: &'b wgpu::Buffer,
    pub(crate) gbuffer: &'b GBuffer,
    pub(crate) tiles: &'b GeometryTiles,
    pub(crate) visibility: &'b wgpu::Buffer,
}

/// One filtered map lookup's inputs (pcf, pcss): the filter uniform, the sample records and the maps.
#[derive(Clone, Copy)]
pub(crate) struct MapFilter<'b> {
    pub(crate) filter: &'b wgpu::Buffer,
    pub(crate) samples: &'b wgpu::Buffer,
    pub(crate) maps: &'b wgpu::TextureView,
}

pub(crate) struct ShadeInputs<'a> {
    pub(crate) frame: &'a wgpu::Buffer,
    pub(crate) samples: &'a wgpu::Buffer,
    pub(crate) weights: &'a wgpu::Buffer,
    pub(crate) gbuffer: &'a GBuffer,
    pub(crate) tiles: &'a GeometryTiles,
    pub(crate) visibility: &'a wgpu::Buffer,
}

impl ShadePass {
    /// `maps`: the representation `main` reads (from_masks reads no maps).
    pub fn new(ctx: &GpuContext, maps: crate::gpu::kernels::MapAccess) -> Result<Self> {
        Ok(Self {
            blocks: BLOCK_SIZES
                .iter()
                .map(|size| {
                    super::ComputeKernel::new_for(ctx, Stage::SHADE, &format!("block{size}"), maps)
                })
                .collect::<Result<_>>()?,
            geometry_tiles: super::ComputeKernel::new(ctx, Stage::SHADE, "geometry_tiles")?,
            from_masks: super::ComputeKernel::new(ctx, Stage::SHADE, "from_masks")?,
        })
    }

    /// A tile list for images of the G-buffer's size, one band.
    pub fn tile_list(&self, ctx: &GpuContext, gbuffer: &GBuffer) -> GeometryTiles {
        self.tile_list_in_bands(ctx, gbuffer, 0)
    }

    /// A tile list with a section per band of `band_rows` rows (0: one band, no section padding).
    pub(crate) fn tile_list_in_bands(
        &self,
        ctx: &GpuContext,
        gbuffer: &GBuffer,
        band_rows: u32,
    ) -> GeometryTiles {
        let (w, h) = (gbuffer.width, gbuffer.height);
        let tiles_x = groups(w, TILE) as u64;
        let (count, section_words) = if band_rows == 0 || band_rows >= h {
            (
                1,
                TILE_LIST_HEADER as u64 + tiles_x * groups(h, TILE) as u64,
            )
        } else {
            // Sections start at 256-byte offsets (the largest binding-offset alignment).
            (
                h.div_ceil(band_rows),
                (TILE_LIST_HEADER as u64 + tiles_x * (band_rows / TILE) as u64).div_ceil(64) * 64,
            )
        };
        let band_rows = if count == 1 { 0 } else { band_rows };
        let bytes = count as u64 * section_words * 4;
        let list = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("geometry tiles"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::INDIRECT
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let header = readback::storage_buffer(
            ctx,
            "geometry tiles header",
            &[0u32, 1, 1, 0],
            wgpu::BufferUsages::COPY_SRC,
        );
        let bands = (0..count)
            .map(|b| Band {
                first_row: b * band_rows,
                rows: if count == 1 {
                    h
                } else {
                    band_rows.min(h - b * band_rows)
                },
                frame: (count > 1).then(|| {
                    ctx.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("band frame"),
                        size: std::mem::size_of::<crate::gpu::structs::GpuFrame>() as u64,
                        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    })
                }),
                tiles_offset: b as u64 * section_words * 4,
                tiles_bytes: section_words * 4,
            })
            .collect();
        GeometryTiles {
            list,
            header,
            bytes,
            band_rows,
            bands,
        }
    }

    /// Lists this frame's tiles with a geometry pixel (after the G-buffer pass) into `tiles`, each
    /// in its band's section.
    pub fn record_geometry_tiles(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::Buffer,
        gbuffer: &GBuffer,
        tiles: &GeometryTiles,
    ) {
        for band in &tiles.bands {
            encoder.copy_buffer_to_buffer(
                &tiles.header,
                0,
                &tiles.list,
                band.tiles_offset,
                TILE_LIST_HEADER as u64 * 4,
            );
        }
        self.geometry_tiles.dispatch(
            ctx,
            encoder,
            bind::shade::GeometryTiles {
                frame: frame.as_entire_binding(),
                gbuffer_position: wgpu::BindingResource::TextureView(&gbuffer.position_view),
                tile_list_build: tiles.list.as_entire_binding(),
            },
            super::Dispatch::Direct([groups(gbuffer.width, TILE), groups(gbuffer.height, TILE), 1]),
        );
    }

    /// Adds samples `first .. first + count` (all in `maps`: a depth array, or a hybrid store's view)
    /// to the visibility buffer.
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &ShadeInputs,
        maps: &wgpu::TextureView,
        first: u32,
        count: u32,
    ) {
        let tiles = inputs.tiles;
        let sample_bytes = std::mem::size_of::<GpuSample>() as u64;
        // Blocks in order, each adding to V in sample order: the sum order is the single loop's.
        for (block, block_count) in blocks(first, count) {
            let kernel = &self.blocks[BLOCK_SIZES
                .iter()
                .position(|&size| size == block_count)
                .expect("a block size")];
            // The block's samples and weights as uniforms (see kernels/shade.wgsl); a smaller block
            // reads only the first `block_count` of each.
            let block_samples = block_uniform(
                ctx,
                "shade block samples",
                SHADE_BLOCK as u64 * sample_bytes,
            );
            let block_weights = block_uniform(ctx, "shade block weights", SHADE_BLOCK as u64 * 4);
            encoder.copy_buffer_to_buffer(
                inputs.samples,
                block as u64 * sample_bytes,
                &block_samples,
                0,
                block_count as u64 * sample_bytes,
            );
            encoder.copy_buffer_to_buffer(
                inputs.weights,
                block as u64 * 4,
                &block_weights,
                0,
                block_count as u64 * 4,
            );
            for band in &tiles.bands {
                kernel.dispatch(
                    ctx,
                    encoder,
                    bind::shade::Block {
                        frame: band.frame(inputs.frame).as_entire_binding(),
                        block_samples: block_samples.as_entire_binding(),
                        block_weights: block_weights.as_entire_binding(),
                        gbuffer_position: wgpu::BindingResource::TextureView(
                            &inputs.gbuffer.position_view,
                        ),
                        gbuffer_normal: wgpu::BindingResource::TextureView(
                            &inputs.gbuffer.normal_view,
                        ),
                        shadow_maps: wgpu::BindingResource::TextureView(maps),
                        visibility: band.pixels(tiles, inputs.visibility, inputs.gbuffer.width, 4),
                        tile_list: band.tiles(tiles),
                    },
                    band.tiles_args(tiles),
                );
            }
        }
    }

    /// Adaptive, scope = global: V = Σ_k ŵ_k · bit_k(p) from the cached lattice masks, a band of
    /// rows per dispatch (`tiles.bands`).
    pub(crate) fn record_masks(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        screen: &Screen,
        weights: &wgpu::Buffer,
        masks: &wgpu::Buffer,
    ) {
        let Screen {
            frame,
            gbuffer,
            tiles,
            visibility,
        } = *screen;
        let mask_bytes = crate::stages::adaptive_buffers::MASK_WORDS as u64 * 4;
        for band in &tiles.bands {
            self.from_masks.dispatch(
                ctx,
                encoder,
                bind::shade::FromMasks {
                    frame: band.frame(frame).as_entire_binding(),
                    weights: weights.as_entire_binding(),
                    gbuffer_position: wgpu::BindingResource::TextureView(&gbuffer.position_view),
                    visibility: band.pixels(tiles, visibility, gbuffer.width, 4),
                    masks: band.pixels(tiles, masks, gbuffer.width, mask_bytes),
                },
                super::Dispatch::Direct([
                    groups(gbuffer.width, WORKGROUP[0]),
                    groups(band.rows, WORKGROUP[1]),
                    1,
                ]),
            );
        }
    }
}

/// A zeroed uniform buffer that a block's copy fills (shade's and estimate's blocks).
pub(super) fn block_uniform(ctx: &GpuContext, label: &str, bytes: u64) -> wgpu::Buffer {
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
            let tail: Vec<u32> = b
                .iter()
                .map(|&(_, size)| size)
                .skip_while(|&s| s == SHADE_BLOCK)
                .collect();
            assert!(
                tail.windows(2).all(|w| w[0] > w[1]),
                "{first}+{count}: {b:?}"
            );
            assert_eq!(
                b.len() as u32,
                count / SHADE_BLOCK + (count % SHADE_BLOCK).count_ones()
            );
        }
    }
}
