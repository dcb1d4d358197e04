//! The one read-back per level, and the per-level record in run.json.

use super::record::{AdaptiveRecord, LevelRecord};
use crate::gpu::readback;
use crate::gpu::structs::{GpuQuad, OVERFLOW_ITEMS, OVERFLOW_PROBES, OVERFLOW_QUADS};
use crate::methods::adaptive::buffers::{
    AdaptiveBuffers, Shape, CONTROL_BYTES, CULL_TILE_WORDS, LATTICE_POINTS, NO_SPLIT, QUAD_CAPACITY,
};
use crate::methods::AdaptiveParams;
use crate::render::gbuffer::GBuffer;
use crate::stages::FrameGpu;
use crate::{Error, Result};

/// What one level's read-back says.
#[derive(Clone, Debug, Default)]
pub struct LevelReport {
    pub level: u32,
    /// Quads evaluated at this level.
    pub quads: Vec<GpuQuad>,
    /// Whether the count stages ran (scope = global skips them at max_level: nothing can split).
    pub evaluated: bool,
    /// Low-quality pixels per evaluated quad.
    pub low_quality: Vec<u32>,
    /// First child index per evaluated quad, or NO_SPLIT.
    pub split_base: Vec<u32>,
    pub next_quad_count: u32,
    pub next_quads: Vec<GpuQuad>,
    /// Lattice samples requested for the next level, sorted.
    pub new_samples: Vec<u32>,
    /// Deepest evaluated level per lattice sample so far.
    pub sample_level: Vec<u32>,
    pub overflow: u32,
    /// Geometry pixels as reproject_count counted them at level 0 (the share criteria's denominator).
    pub geometry_pixels: u32,
    /// scope = local: probe items compact appended for the next level (uniform pixels of split quads).
    pub probes: u32,
    /// scope = local: (pixel, quad) items evaluated at this level.
    pub items: u32,
    /// scope = local: the items (or probes, whichever is more) this level appended for the next,
    /// counted past the list's capacity: what a list grown after an overflow must hold at least.
    pub appended: u32,
    /// scope = local with scissor: texel rectangle [min x, min y, max x, max y] per lattice sample.
    pub rects: Vec<[u32; 4]>,
    /// scope = local with culling: indices kept per lattice sample so far (0 where never culled),
    /// and, with pictures, this level's culling tiles (CULL_TILE_WORDS per lattice sample).
    pub triangles: Vec<u32>,
    pub tiles: Vec<u32>,
    /// Level 0's comparison map (packed bytes, quad 0; every quad's when kept) and this
    /// level's flags, for pictures and twin tests.
    pub counts: Option<Vec<u32>>,
    /// The word states reproject_count wrote (`counts` is already made whole with them).
    pub word_state: Option<Vec<u32>>,
    pub flags: Option<Vec<u32>>,
    /// Captured for twin tests: the per-pixel lattice masks as this level's counting read them.
    pub masks: Option<Vec<u32>>,
    /// Captured for twin tests (scope = local): the samples each pixel consulted so far.
    pub consulted: Option<Vec<u32>>,
    /// scope = local: shadow-map lookups at this level, one per (pixel, sample) pair consulted for
    /// the first time in the frame.
    pub lookups: u32,
}

impl LevelReport {
    /// The run's error when a counter overflowed its buffer at this level (GpuControl.overflow's
    /// bits, the one place they are decoded): overflow is reported, never clipped.
    pub(crate) fn overflow_error(&self, level: u32) -> Option<Error> {
        let cause = if self.overflow & OVERFLOW_ITEMS != 0 {
            "the (pixel, quad) item list exceeded its capacity"
        } else if self.overflow & OVERFLOW_PROBES != 0 {
            "the probe list exceeded its capacity"
        } else if self.overflow & OVERFLOW_QUADS != 0 {
            "the quad list exceeded 256"
        } else if self.overflow != 0 {
            "an unknown counter overflowed"
        } else {
            return None;
        };
        Some(Error::Overflow(format!(
            "adaptive level {level}: {cause} (flags {:#x}); the run is not valid",
            self.overflow
        )))
    }

    /// Whether the overflow (if any) is one a longer item list removes: items or probes, not the
    /// quad list, whose 256 the lattice fixes.
    pub(crate) fn item_overflow(&self) -> bool {
        self.overflow & (OVERFLOW_ITEMS | OVERFLOW_PROBES) != 0
            && self.overflow & OVERFLOW_QUADS == 0
    }
}

/// What one level's record holds besides its fixed parts: `n` quads evaluated, the culling
/// counts and tiles, the pictures' comparison map and flags, the twins' kept buffers.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LevelRead {
    pub(crate) n: u64,
    pub(crate) kept: bool,
    pub(crate) pictures: bool,
    pub(crate) intermediates: bool,
    /// scope = local: the kept buffers include the consulted samples.
    pub(crate) local: bool,
}

/// The buffers (and byte counts) of one level's record, in the order `parse_level` reads them.
pub(crate) fn level_parts<'a>(
    b: &'a AdaptiveBuffers,
    next_quads: &'a wgpu::Buffer,
    kept: Option<&'a wgpu::Buffer>,
    r: LevelRead,
) -> Vec<(&'a wgpu::Buffer, u64)> {
    let lattice = LATTICE_POINTS as u64 * 4;
    let mut parts: Vec<(&wgpu::Buffer, u64)> = vec![
        (&b.control, CONTROL_BYTES),
        (&b.decisions.new_samples, lattice),
        (next_quads, QUAD_CAPACITY as u64 * 16),
        (&b.low.per_quad, QUAD_CAPACITY as u64 * 4),
        (&b.decisions.sample_level, lattice),
        (&b.decisions.split_base, QUAD_CAPACITY as u64 * 4),
        (&b.footprints.rects, lattice * 4),
        (&b.items.total, 4),
    ];
    if let Some(kept) = kept.filter(|_| r.kept) {
        parts.push((kept, lattice));
        if r.pictures {
            parts.push((&b.footprints.tiles, lattice * CULL_TILE_WORDS as u64));
        }
    }
    if r.pictures {
        parts.push((
            &b.counts.maps,
            b.shape.counts_bytes_per_quad() * if r.intermediates { r.n } else { 1 },
        ));
        parts.push((&b.counts.word_state, b.shape.counts_bytes_per_quad()));
        parts.push((&b.low.flags, b.shape.flags_bytes_per_quad() * r.n));
    }
    if r.intermediates {
        parts.push((&b.masks.lit, b.shape.mask_bytes()));
        if r.local {
            parts.push((&b.masks.consulted, b.shape.mask_bytes()));
        }
    }
    parts
}

/// The level a record belongs to: its number, the quads it evaluated, and whether its count
/// stages ran (scope = global skips them at max_level).
pub(crate) struct LevelOf {
    pub(crate) level: u32,
    pub(crate) quads: Vec<GpuQuad>,
    pub(crate) evaluated: bool,
}

/// The one read-back of a level (the waiting loop): its record, `next_quads` and (culling)
/// `kept` among its buffers.
pub(crate) fn read_level(
    fg: &FrameGpu,
    b: &AdaptiveBuffers,
    of: LevelOf,
    next_quads: &wgpu::Buffer,
    kept: Option<&wgpu::Buffer>,
    r: LevelRead,
) -> Result<LevelReport> {
    let ctx = fg.ctx;
    let parts = level_parts(b, next_quads, kept, r);
    let total: u64 = parts.iter().map(|(_, s)| s).sum();
    let staging = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("level readback"),
        size: total,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    let mut offset = 0;
    for (buf, size) in &parts {
        enc.copy_buffer_to_buffer(buf, 0, &staging, offset, *size);
        offset += size;
    }
    ctx.queue.submit([enc.finish()]);
    let words: Vec<u32> = readback::map_staging(ctx, &staging)?;
    Ok(parse_level(b, &words, of, r))
}

/// Reads one level's record (`level_parts`' layout) from `words`.
pub(crate) fn parse_level(
    b: &AdaptiveBuffers,
    words: &[u32],
    of: LevelOf,
    r: LevelRead,
) -> LevelReport {
    let LevelOf {
        level,
        quads,
        evaluated,
    } = of;
    let n = r.n;
    let lattice = LATTICE_POINTS as u64 * 4;
    let quad_bytes = QUAD_CAPACITY as u64 * 16;
    let tile_bytes = lattice * CULL_TILE_WORDS as u64;
    let counts_len = b.shape.counts_bytes_per_quad() * if r.intermediates { n } else { 1 };
    let mask_len = b.shape.mask_bytes();
    let mut at = 0usize;
    let mut take = |len: u64| {
        let s = words[at..at + (len / 4) as usize].to_vec();
        at += (len / 4) as usize;
        s
    };
    let control = take(CONTROL_BYTES);
    let new_all = take(lattice);
    let next_raw = take(quad_bytes);
    let counters = take(QUAD_CAPACITY as u64 * 4);
    let sample_level = take(lattice);
    let split_base = take(QUAD_CAPACITY as u64 * 4);
    let rects_raw = take(lattice * 4);
    let item_total = take(4)[0];
    let triangles = if r.kept {
        take(lattice)
    } else {
        vec![0; LATTICE_POINTS as usize]
    };
    let tiles = if r.kept && r.pictures {
        take(tile_bytes)
    } else {
        Vec::new()
    };
    let (counts, word_state, flags) = if r.pictures {
        let mut counts = take(counts_len);
        let word_state = take(b.shape.counts_bytes_per_quad());
        Shape::dense_counts(&mut counts, &word_state);
        (
            Some(counts),
            Some(word_state),
            Some(take(b.shape.flags_bytes_per_quad() * n)),
        )
    } else {
        (None, None, None)
    };
    let masks = if r.intermediates {
        Some(take(mask_len))
    } else {
        None
    };
    let consulted = if r.intermediates && r.local {
        Some(take(mask_len))
    } else {
        None
    };
    let next_quad_count = control[0].min(QUAD_CAPACITY);
    let new_count = (control[1] as usize).min(LATTICE_POINTS as usize);
    let mut new_samples = new_all[..new_count].to_vec();
    new_samples.sort_unstable();
    let next_quads: Vec<GpuQuad> =
        bytemuck::cast_slice::<u32, GpuQuad>(&next_raw)[..next_quad_count as usize].to_vec();
    LevelReport {
        level,
        evaluated,
        low_quality: if evaluated {
            counters[..n as usize].to_vec()
        } else {
            vec![0; n as usize]
        },
        split_base: split_base[..n as usize].to_vec(),
        quads,
        next_quad_count,
        next_quads,
        new_samples,
        sample_level,
        overflow: control[2],
        geometry_pixels: control[4],
        probes: control[5],
        items: if r.local { item_total } else { 0 },
        appended: if r.local {
            control[3].max(control[5])
        } else {
            0
        },
        lookups: if r.local { control[6] } else { 0 },
        triangles,
        tiles,
        rects: rects_raw
            .chunks_exact(4)
            .map(|r| [r[0], r[1], r[2], r[3]])
            .collect(),
        counts,
        word_state,
        flags,
        masks,
        consulted,
    }
}

pub(crate) fn record(
    p: &AdaptiveParams,
    trace: &super::AdaptiveTrace,
    syncs: u32,
    consulted: Option<&[u32]>,
    g: &GBuffer,
) -> AdaptiveRecord {
    let pixels = g.width as u64 * g.height as u64;
    let levels: Vec<LevelRecord> = trace
        .levels
        .iter()
        .map(|r| LevelRecord {
            level: r.level,
            active_quads: r.quads.len(),
            quads: r
                .quads
                .iter()
                .map(|q| [q.i, q.j, q.size, q.parent])
                .collect(),
            low_quality_per_quad: r.low_quality.clone(),
            split_quads: r.split_base.iter().filter(|&&s| s != NO_SPLIT).count(),
            new_samples: r.new_samples.len(),
            lookups: (p.scope == crate::methods::Scope::Local).then_some(r.lookups as u64),
            pixels_evaluated: if p.scope == crate::methods::Scope::Local {
                r.items as u64
            } else if r.evaluated {
                pixels * r.quads.len() as u64
            } else {
                0
            },
        })
        .collect();
    let mut out = AdaptiveRecord {
        levels,
        syncs,
        shadow_maps_used: trace.rendered.clone(),
        triangles_per_map: trace.triangles.clone(),
        triangles_per_map_mean: trace.triangles.iter().sum::<u64>() as f64
            / trace.triangles.len().max(1) as f64,
        culled_maps: trace.culled.len(),
        weights: weights_rule(p),
        samples_per_pixel_mean: None,
        samples_per_pixel_max: None,
        hybrid: None,
        steer: None,
        steer_raster: None,
    };
    if let Some(masks) = consulted {
        let counts: Vec<u32> = masks
            .chunks_exact(10)
            .map(|m| m.iter().map(|w| w.count_ones()).sum())
            .collect();
        let geo: Vec<u32> = counts.iter().copied().filter(|&c| c > 0).collect();
        let mean = geo.iter().map(|&c| c as f64).sum::<f64>() / geo.len().max(1) as f64;
        out.samples_per_pixel_mean = Some(mean);
        out.samples_per_pixel_max = Some(geo.iter().max().copied().unwrap_or(0));
    }
    out
}

/// The weight rule a run used, in words, for run.json.
fn weights_rule(p: &crate::methods::AdaptiveParams) -> String {
    use crate::methods::{Layout, Scope, Weights};
    let rule = match (p.scope, p.weights) {
        (Scope::Local, _) => "area quadrature along each pixel's quad path (scope = local)",
        (_, Weights::Level) => "level (seed rule: 1/(2^level+1)^2, normalised)",
        (_, Weights::Area) => "area (leaf quads, mean of corners)",
        (_, Weights::Coons) => "coons (leaf quads through every rendered sample on their edges)",
    };
    if p.layout == Layout::Centred {
        format!("{rule}, plus the border strips of the centred layout")
    } else {
        rule.to_string()
    }
}
