//! GPU buffers of the adaptive method, sized in one place.

use crate::gpu::{readback, GpuContext};
use crate::gpu::structs::{GpuQuad, GpuSample};
use crate::{Error, Result};

pub const LATTICE_SIDE: u32 = 17;
pub const LATTICE_POINTS: u32 = 289;
pub const MASK_WORDS: u32 = 10;
/// Quads of one level: at most 4^4 = 256 (level 4 of the 17x17 lattice).
pub const QUAD_CAPACITY: u32 = 256;
pub const NO_SPLIT: u32 = u32::MAX;
/// Culling tiles per side of a map, and the u32 words of one sample's tiles (common.wgsl): per
/// tile 0, or the largest depth limit its pixels test (f32 bits).
pub const CULL_TILES: u32 = 256;
pub const CULL_TILE_WORDS: u32 = CULL_TILES * CULL_TILES;
/// word_state of a word whose comparison-map words differ by quad (common.wgsl MIXED_WORD).
pub const MIXED_WORD: u32 = u32::MAX;
pub const CONTROL_BYTES: u64 = std::mem::size_of::<crate::gpu::structs::GpuControl>() as u64;

pub struct AdaptiveBuffers {
    pub width: u32,
    pub height: u32,
    pub words_per_row: u32,
    pub flag_words_per_row: u32,
    /// Quads whose comparison maps fit at once (dense mode batches beyond it).
    pub count_quads: u32,
    pub item_capacity: u32,
    pub samples: wgpu::Buffer,
    /// Per pixel, MASK_WORDS words: bit k = lattice sample k lights the pixel (tested samples only).
    pub masks: wgpu::Buffer,
    /// scope = local: the same layout, bit k = the pixel consulted sample k (shadow_test tested it).
    pub consulted: wgpu::Buffer,
    pub quads: [wgpu::Buffer; 2],
    pub counts: wgpu::Buffer,
    /// One word per comparison-map word: its bytes when uniform (the same in every quad's map, which
    /// then holds nothing for it), else MIXED_WORD. Scope = local never writes it: all MIXED_WORD.
    pub word_state: wgpu::Buffer,
    pub flags: wgpu::Buffer,
    pub quad_counters: wgpu::Buffer,
    pub control: wgpu::Buffer,
    pub lattice_state: wgpu::Buffer,
    pub new_samples: wgpu::Buffer,
    pub sample_level: wgpu::Buffer,
    pub split_base: wgpu::Buffer,
    pub dispatch_args: wgpu::Buffer,
    pub weights: wgpu::Buffer,
    pub items: [wgpu::Buffer; 2],
    pub item_total: wgpu::Buffer,
    pub list_args: wgpu::Buffer,
    /// scope = local: probes (uniform pixels of split quads) for the next level, their count and dispatch.
    pub probes: wgpu::Buffer,
    pub probe_total: wgpu::Buffer,
    pub probe_args: wgpu::Buffer,
    pub visibility_fixed: wgpu::Buffer,
    pub rects: wgpu::Buffer,
    /// scope = local: CULL_TILE_WORDS per lattice sample, per culling tile the largest depth limit its pixels test.
    pub tiles: wgpu::Buffer,
}

impl AdaptiveBuffers {
    /// wgpu zero-fills a buffer lazily at its first use; doing it here keeps that out of the frame.
    pub fn zero_fill(&self, ctx: &GpuContext) -> Result<()> {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        for buf in [
            &self.masks, &self.consulted, &self.quads[0], &self.quads[1], &self.counts, &self.flags, &self.quad_counters, &self.control,
            &self.lattice_state, &self.new_samples, &self.sample_level, &self.split_base, &self.weights, &self.items[0],
            &self.items[1], &self.item_total, &self.visibility_fixed, &self.rects, &self.probes, &self.probe_total,
        ] {
            enc.clear_buffer(buf, 0, None);
        }
        ctx.queue.submit([enc.finish()]);
        ctx.wait()
    }

    /// Between frames of one renderer: like `zero_fill`, but without the item and probe lists and
    /// the comparison maps, which every level writes (or clears) before it reads them; they are the
    /// large ones.
    pub fn reset_frame(&self, ctx: &GpuContext) -> Result<()> {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        for buf in [
            &self.masks, &self.consulted, &self.quads[0], &self.quads[1], &self.flags, &self.quad_counters, &self.control,
            &self.lattice_state, &self.new_samples, &self.sample_level, &self.split_base, &self.weights,
            &self.item_total, &self.visibility_fixed, &self.rects, &self.probe_total,
        ] {
            enc.clear_buffer(buf, 0, None);
        }
        ctx.queue.submit([enc.finish()]);
        ctx.wait()
    }

    pub fn counts_bytes_per_quad(&self) -> u64 {
        self.height as u64 * self.words_per_row as u64 * 4
    }
    /// The comparison maps of `n` quads as every quad's full map: uniform words from `word_state`.
    pub fn dense_counts(&self, counts: &mut [u32], word_state: &[u32]) {
        for map in counts.chunks_exact_mut(word_state.len()) {
            for (c, &s) in map.iter_mut().zip(word_state) {
                if s != MIXED_WORD {
                    *c = s;
                }
            }
        }
    }
    pub fn flags_bytes_per_quad(&self) -> u64 {
        self.height as u64 * self.flag_words_per_row as u64 * 4
    }

    /// `local`: items, fixed-point visibility and rectangles are needed, and every quad of a level
    /// must fit in one comparison-map buffer.
    /// `item_cap` lowers the item list's capacity (`adaptive:items`).
    pub fn new(ctx: &GpuContext, width: u32, height: u32, samples: &[GpuSample], local: bool, item_cap: Option<u32>) -> Result<Self> {
        let limits = ctx.limits();
        let max_binding = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        let words_per_row = width.div_ceil(4);
        let flag_words_per_row = width.div_ceil(32);
        let pixels = width as u64 * height as u64;
        let per_quad = height as u64 * words_per_row as u64 * 4;
        let count_quads = (max_binding / per_quad).min(QUAD_CAPACITY as u64) as u32;
        let mask_bytes = pixels * MASK_WORDS as u64 * 4;
        if count_quads == 0 || mask_bytes > max_binding {
            return Err(Error::Limit(format!(
                "adaptive at {width}x{height}: per-pixel lattice masks need {} MiB, over this device's storage binding limit of {} MiB",
                mask_bytes >> 20,
                max_binding >> 20
            )));
        }
        if local && count_quads < QUAD_CAPACITY {
            return Err(Error::Limit(format!(
                "adaptive scope=local at {width}x{height}: the comparison maps of 256 level-4 quads need {} MiB, over the storage binding limit of {} MiB; use a smaller resolution or scope=global (which batches)",
                (per_quad * 256) >> 20,
                max_binding >> 20
            )));
        }
        // Items: every penumbra pixel of a split quad becomes 4, so a pixel on a silhouette can reach
        // ~4·2^level items; take what one binding holds. Overflow is reported, never clipped.
        let mut item_capacity = if local { ((max_binding / 8).min(pixels * 32)) as u32 } else { 1 };
        if let Some(cap) = item_cap {
            item_capacity = item_capacity.min(cap.max(1));
        }
        let storage = |label: &str, bytes: u64| readback::zeroed_storage(ctx, label, bytes);
        let indirect = |label: &str| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 16,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let quad_bytes = QUAD_CAPACITY as u64 * std::mem::size_of::<GpuQuad>() as u64;
        let batch = if local { QUAD_CAPACITY } else { count_quads } as u64;
        Ok(Self {
            width,
            height,
            words_per_row,
            flag_words_per_row,
            count_quads,
            item_capacity,
            samples: readback::storage_buffer(ctx, "lattice samples", samples, wgpu::BufferUsages::empty()),
            masks: storage("lattice masks", mask_bytes),
            consulted: storage("consulted samples", if local { mask_bytes } else { 4 }),
            quads: [storage("quads a", quad_bytes), storage("quads b", quad_bytes)],
            counts: storage("comparison maps", per_quad * batch),
            word_state: readback::storage_buffer(ctx, "comparison word states", &vec![MIXED_WORD; (per_quad / 4) as usize], wgpu::BufferUsages::empty()),
            flags: storage("low-quality flags", height as u64 * flag_words_per_row as u64 * 4 * batch),
            quad_counters: storage("quad counters", QUAD_CAPACITY as u64 * 4),
            control: storage("control", CONTROL_BYTES),
            lattice_state: storage("lattice state", LATTICE_POINTS as u64 * 4),
            new_samples: storage("new samples", LATTICE_POINTS as u64 * 4),
            sample_level: storage("sample levels", LATTICE_POINTS as u64 * 4),
            split_base: storage("split base", QUAD_CAPACITY as u64 * 4),
            dispatch_args: indirect("dense dispatch args"),
            weights: storage("weights", LATTICE_POINTS as u64 * 4),
            items: [storage("items a", item_capacity as u64 * 8), storage("items b", item_capacity as u64 * 8)],
            item_total: storage("item total", 16),
            list_args: indirect("list dispatch args"),
            probes: storage("probes", if local { item_capacity as u64 * 8 } else { 8 }),
            probe_total: storage("probe total", 16),
            probe_args: indirect("probe dispatch args"),
            visibility_fixed: storage("visibility fixed", if local { pixels * 4 } else { 4 }),
            rects: storage("scissor rects", LATTICE_POINTS as u64 * 16),
            tiles: storage("cull tiles", if local { LATTICE_POINTS as u64 * CULL_TILE_WORDS as u64 * 4 } else { 16 }),
        })
    }
}
