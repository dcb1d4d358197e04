//! GPU buffers of the adaptive method, sized in one place.

use crate::gpu::size_plan::SizeNeed;
use crate::gpu::structs::{GpuQuad, GpuSample};
use crate::gpu::{readback, GpuContext};
use crate::{Error, Result};

pub use crate::stages::adaptive_buffers::*;

/// The adaptive method's buffers, grouped by the passes that write them.
pub struct AdaptiveBuffers {
    pub shape: Shape,
    pub samples: wgpu::Buffer,
    pub quads: [wgpu::Buffer; 2],
    pub control: wgpu::Buffer,
    pub masks: Masks,
    pub counts: CountMaps,
    pub low: LowQuality,
    pub decisions: Decisions,
    pub items: ItemLists,
    pub footprints: Footprints,
    pub weights: wgpu::Buffer,
}

impl AdaptiveBuffers {
    /// wgpu zero-fills a buffer lazily at its first use; doing it here keeps that out of the frame.
    pub(crate) fn zero_fill(&self, ctx: &GpuContext) -> Result<()> {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        for buf in [
            &self.masks.lit,
            &self.masks.consulted,
            &self.quads[0],
            &self.quads[1],
            &self.counts.maps,
            &self.low.flags,
            &self.low.per_quad,
            &self.control,
            &self.decisions.lattice_state,
            &self.decisions.new_samples,
            &self.decisions.sample_level,
            &self.decisions.split_base,
            &self.weights,
            &self.items.items[0],
            &self.items.items[1],
            &self.items.total,
            &self.items.visibility_fixed,
            &self.footprints.rects,
            &self.items.probes,
            &self.items.probe_total,
        ] {
            enc.clear_buffer(buf, 0, None);
        }
        ctx.queue.submit([enc.finish()]);
        ctx.wait()
    }

    /// Between frames of one renderer: like `zero_fill`, but without the item and probe lists and
    /// the comparison maps, which every level writes (or clears) before it reads them; they are the
    /// large ones.
    pub(crate) fn reset_frame(&self, ctx: &GpuContext) -> Result<()> {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        for buf in [
            &self.masks.lit,
            &self.masks.consulted,
            &self.quads[0],
            &self.quads[1],
            &self.low.flags,
            &self.low.per_quad,
            &self.control,
            &self.decisions.lattice_state,
            &self.decisions.new_samples,
            &self.decisions.sample_level,
            &self.decisions.split_base,
            &self.weights,
            &self.items.total,
            &self.items.visibility_fixed,
            &self.footprints.rects,
            &self.items.probe_total,
        ] {
            enc.clear_buffer(buf, 0, None);
        }
        ctx.queue.submit([enc.finish()]);
        ctx.wait()
    }

    /// `local`: items, fixed-point visibility and rectangles are needed, and every quad of a level
    /// must fit in one comparison-map buffer.
    /// `item_cap`: the item list's capacity (`adaptive:items`, or what an overflow grew it to).
    pub fn new(
        ctx: &GpuContext,
        width: u32,
        height: u32,
        samples: &[GpuSample],
        local: bool,
        item_cap: Option<u32>,
    ) -> Result<Self> {
        let limits = ctx.limits();
        let max_binding = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let words_per_row = width.div_ceil(4);
        let flag_words_per_row = width.div_ceil(32);
        let pixels = width as u64 * height as u64;
        let per_quad = height as u64 * words_per_row as u64 * 4;
        let count_quads = count_quads(width, height, &limits);
        let mask_bytes = pixels * MASK_WORDS as u64 * 4;
        // Global scope binds the masks by bands of rows (stages::shade::Band); local scope whole.
        if count_quads == 0 || (local && mask_bytes > max_binding) {
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
        // ~4·2^level items; start at 32 per pixel (or `item_cap`), at most what one binding holds.
        // Overflow is reported, never clipped; the method grows the list and runs the frame again
        // (methods::adaptive::growth).
        let item_capacity = if local {
            item_cap
                .map_or(pixels * 32, |c| c.max(1) as u64)
                .min(max_items(ctx)) as u32
        } else {
            1
        };
        let storage = |label: &str, bytes: u64| readback::zeroed_storage(ctx, label, bytes);
        let indirect = |label: &str| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 16,
                // COPY_SRC: twin tests read the dispatch sizes back.
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::INDIRECT
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let quad_bytes = QUAD_CAPACITY as u64 * std::mem::size_of::<GpuQuad>() as u64;
        let batch = if local { QUAD_CAPACITY } else { count_quads } as u64;
        Ok(Self {
            shape: Shape {
                width,
                height,
                words_per_row,
                flag_words_per_row,
                count_quads,
                item_capacity,
            },
            samples: readback::storage_buffer(
                ctx,
                "lattice samples",
                samples,
                wgpu::BufferUsages::empty(),
            ),
            quads: [
                storage("quads a", quad_bytes),
                storage("quads b", quad_bytes),
            ],
            control: storage("control", CONTROL_BYTES),
            masks: Masks {
                lit: storage("lattice masks", mask_bytes),
                consulted: storage("consulted samples", if local { mask_bytes } else { 4 }),
            },
            counts: CountMaps {
                maps: storage("counts", per_quad * batch),
                word_state: readback::storage_buffer(
                    ctx,
                    "comparison word states",
                    &vec![MIXED_WORD; (per_quad / 4) as usize],
                    wgpu::BufferUsages::empty(),
                ),
            },
            low: LowQuality {
                flags: storage(
                    "low-quality flags",
                    height as u64 * flag_words_per_row as u64 * 4 * batch,
                ),
                per_quad: storage("quad counters", QUAD_CAPACITY as u64 * 4),
            },
            decisions: Decisions {
                lattice_state: storage("lattice state", LATTICE_POINTS as u64 * 4),
                new_samples: storage("new samples", LATTICE_POINTS as u64 * 4),
                sample_level: storage("sample levels", LATTICE_POINTS as u64 * 4),
                split_base: storage("split base", QUAD_CAPACITY as u64 * 4),
                dispatch_args: indirect("dense dispatch args"),
                held: readback::storage_buffer(
                    ctx,
                    "held quads",
                    &[u32::MAX; crate::stages::adaptive_buffers::HELD_WORDS as usize],
                    wgpu::BufferUsages::empty(),
                ),
            },
            items: ItemLists {
                items: [
                    storage("items a", item_capacity as u64 * 8),
                    storage("items b", item_capacity as u64 * 8),
                ],
                total: storage("item total", 16),
                list_args: indirect("list dispatch args"),
                probes: storage("probes", if local { item_capacity as u64 * 8 } else { 8 }),
                probe_total: storage("probe total", 16),
                probe_args: indirect("probe dispatch args"),
                visibility_fixed: storage("visibility fixed", if local { pixels * 4 } else { 4 }),
            },
            footprints: Footprints {
                rects: storage("scissor rects", LATTICE_POINTS as u64 * 16),
                tiles: storage(
                    "cull tiles",
                    if local {
                        LATTICE_POINTS as u64 * CULL_TILE_WORDS as u64 * 4
                    } else {
                        16
                    },
                ),
            },
            weights: storage("weights", LATTICE_POINTS as u64 * 4),
        })
    }
}

/// The most (pixel, quad) items one list can hold on this device: one binding of 8-byte items.
pub fn max_items(ctx: &GpuContext) -> u64 {
    let limits = ctx.limits();
    (limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size)
        / 8)
    .min(u32::MAX as u64)
}

/// Quads whose comparison maps (one byte per pixel each) fit one binding, at most a level's.
fn count_quads(width: u32, height: u32, limits: &wgpu::Limits) -> u32 {
    let max_binding = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    let per_quad = height as u64 * width.div_ceil(4) as u64 * 4;
    (max_binding / per_quad).min(QUAD_CAPACITY as u64) as u32
}

/// The screen-sized buffers `AdaptiveBuffers::new` creates, by their labels (the masks by bands
/// of rows under global scope, the rest whole):
/// the frame's size plan (`methods::sizes`) checks them before anything is built.
pub(crate) fn size_needs(
    scene: &crate::scene::Scene,
    local: bool,
    limits: &wgpu::Limits,
) -> Vec<SizeNeed> {
    let (width, height) = (scene.render.width, scene.render.height);
    let pixels = width as u64 * height as u64;
    let per_quad = height as u64 * width.div_ceil(4) as u64 * 4;
    let flags_per_quad = height as u64 * width.div_ceil(32) as u64 * 4;
    // At least one quad's map must fit; local scope needs a whole level's at once.
    let batch = if local {
        QUAD_CAPACITY
    } else {
        count_quads(width, height, limits).max(1)
    } as u64;
    let mask_bytes = pixels * MASK_WORDS as u64 * 4;
    let mut needs = vec![
        crate::methods::sizes::per_pixel_in(
            scene,
            "lattice masks",
            MASK_WORDS as u64 * 4,
            !local,
            limits,
        ),
        SizeNeed::binding("counts", per_quad * batch),
        SizeNeed::binding("comparison word states", per_quad),
        SizeNeed::binding("low-quality flags", flags_per_quad * batch),
    ];
    if local {
        needs.push(SizeNeed::binding("consulted samples", mask_bytes));
        needs.push(SizeNeed::binding("visibility fixed", pixels * 4));
    }
    needs
}

impl AdaptiveBuffers {
    /// The screen-sized buffers, by label, as [`size_needs`] plans them.
    pub(crate) fn screen_sized(&self) -> Vec<(String, u64)> {
        let mut out = vec![
            ("lattice masks".to_string(), self.masks.lit.size()),
            ("counts".to_string(), self.counts.maps.size()),
            (
                "comparison word states".to_string(),
                self.counts.word_state.size(),
            ),
            ("low-quality flags".to_string(), self.low.flags.size()),
        ];
        // Local scope: the consulted masks are as large as the lit ones (4 bytes otherwise).
        if self.masks.consulted.size() == self.masks.lit.size() {
            out.push(("consulted samples".to_string(), self.masks.consulted.size()));
            out.push((
                "visibility fixed".to_string(),
                self.items.visibility_fixed.size(),
            ));
        }
        out
    }

    /// scope = local: item and probe lists of `capacity` items in place of the current ones (each
    /// old list is freed as its successor is made), cleared here as `zero_fill` clears the first
    /// ones; the rest is kept, and `reset_frame` restarts it.
    pub(crate) fn grow_items(&mut self, ctx: &GpuContext, capacity: u32) -> Result<()> {
        let bytes = capacity as u64 * 8;
        self.items.items = [
            readback::zeroed_storage(ctx, "items a", bytes),
            readback::zeroed_storage(ctx, "items b", bytes),
        ];
        self.items.probes = readback::zeroed_storage(ctx, "probes", bytes);
        self.shape.item_capacity = capacity;
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        for buf in [
            &self.items.items[0],
            &self.items.items[1],
            &self.items.probes,
        ] {
            enc.clear_buffer(buf, 0, None);
        }
        ctx.queue.submit([enc.finish()]);
        ctx.wait()
    }

    pub(crate) fn requests(&self) -> Requests<'_> {
        Requests {
            samples: &self.samples,
            decisions: &self.decisions,
            control: &self.control,
        }
    }
}
