//! One adaptive frame, split by scope over shared per-level steps. `levels` is the one level loop:
//!   new maps ─► count (global: dense; local: probe + item list) ─► subdivide [─► compact] ─► end
//! Whether the host reads each level back (`Waiting`, steer = cpu) or the GPU steers the next
//! level itself (`steer::Steered`, steer = gpu) is the `Steering` it runs with; the steps are the same.

use super::buffers::{Level, Shape, CONTROL_BYTES, CULL_TILE_WORDS, LATTICE_POINTS, QUAD_CAPACITY};
pub(super) use super::context::Frame;
use super::levels::{self, LevelReport};
use super::maps::{render_new, MapStore, NewMaps};
use super::params::SplitRule;
use super::{candidates, pictures, sample_weights, AdaptiveTrace, Prepared, CORNERS, ROOT};
use crate::gpu::readback;
use crate::gpu::structs::{
    GpuControl, GpuLevel, GpuSample, SPLIT_ALWAYS, SPLIT_NEVER, SPLIT_SHARE, SPLIT_THRESHOLD,
};
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::methods::{AdaptiveParams, MethodOutput};
use crate::stages::compact::CompactInputs;
use crate::stages::shadow_test::{LocalWork, TestFrame};
use crate::stages::{groups, FrameGpu, LINE_WORKGROUP};
use crate::Result;

impl<'a> Frame<'a> {
    /// The uniform of one level (a batch of `quad_count` quads from `first_quad` in dense mode).
    pub(crate) fn uniform(&self, level: u32, quad_count: u32, first_quad: u32) -> wgpu::Buffer {
        readback::uniform_buffer(
            self.fg.ctx,
            "level",
            &level_uniform(self.p, self.b.shape, level, quad_count, first_quad),
        )
    }

    /// What every shadow test of the frame reads and writes besides its maps.
    pub(crate) fn test_frame(&self) -> TestFrame<'_> {
        TestFrame {
            frame: &self.fg.frame_buffer,
            gbuffer: &self.fg.gbuffer,
            tiles: &self.fg.geometry_tiles,
            rq: self.b.requests(),
            out: &self.b.masks,
        }
    }

    /// What the count passes read of level `uniform` whose quads are `quads[cur]`.
    pub(crate) fn level<'l>(&'l self, uniform: &'l wgpu::Buffer, cur: usize) -> Level<'l> {
        Level {
            frame: &self.fg.frame_buffer,
            uniform,
            quads: &self.b.quads[cur],
            control: &self.b.control,
            cur,
            shape: self.b.shape,
        }
    }

    /// Level 0 (queue writes, ahead of the frame's commands): the counters at zero, the whole light
    /// as the one quad, its four corners requested.
    pub(crate) fn begin(&self) {
        let (ctx, b) = (self.fg.ctx, self.b);
        ctx.queue
            .write_buffer(&b.control, 0, &[0u8; CONTROL_BYTES as usize]);
        ctx.queue
            .write_buffer(&b.quads[0], 0, bytemuck::bytes_of(&ROOT));
        let mut state = vec![0u32; LATTICE_POINTS as usize];
        for k in CORNERS {
            state[k as usize] = 1;
        }
        ctx.queue
            .write_buffer(&b.decisions.lattice_state, 0, bytemuck::cast_slice(&state));
    }
}

/// How the level loop learns each level's decisions.
pub(super) trait Steering {
    /// The level's uniform (all its quads).
    fn uniform(&mut self, fx: &Frame, level: u32) -> wgpu::Buffer;
    /// Renders the level's new maps (scope = global: and caches their tests), then zeroes the
    /// level's counters, which those tests may read.
    fn new_maps(
        &mut self,
        fx: &Frame,
        timer: &mut StageTimer,
        level: u32,
        lv: &wgpu::Buffer,
    ) -> Result<()>;
    /// The level's quad count where the host knows it (to batch the comparison maps).
    fn quad_count(&self) -> Option<u32>;
    /// Every map rendered so far, as scope = local's list tests read them.
    fn maps(&self) -> [&wgpu::TextureView; 2];
    /// After subdivide (and compact): the level's record. False when no level follows.
    fn end_level(
        &mut self,
        fx: &Frame,
        timer: &mut StageTimer,
        level: u32,
        lv: &wgpu::Buffer,
        evaluated: bool,
    ) -> Result<bool>;
}

/// The level loop. `evaluated` (what the level's record says): the low-quality flags exist.
pub(super) fn levels(
    fx: &Frame,
    timer: &mut StageTimer,
    steering: &mut impl Steering,
) -> Result<()> {
    let max_level = fx.p.max_level;
    for level in 0..=max_level {
        let (cur, nxt) = ((level % 2) as usize, 1 - (level % 2) as usize);
        let lv = steering.uniform(fx, level);
        steering.new_maps(fx, timer, level, &lv)?;
        let evaluated = if fx.local {
            count_items(
                fx,
                timer,
                level,
                &fx.level(&lv, cur),
                steering.quad_count(),
                steering.maps(),
            )?;
            // The last level adds its counts to V at once: no comparison maps, no flags.
            level < max_level
        } else {
            // The counts only feed the split rule: a rule that cannot depend on them (always,
            // never) and the last level (nothing splits) skip the count stages.
            let evaluate = level < max_level && counted(fx.p, level);
            if evaluate {
                count_dense(fx, timer, level, &lv, cur, steering.quad_count())?;
            }
            evaluate
        };
        subdivide(fx, timer, &lv, cur, nxt)?;
        if fx.local && level < max_level {
            compact(fx, timer, level, &lv, cur, nxt)?;
        }
        if !steering.end_level(fx, timer, level, &lv, evaluated)? {
            break;
        }
    }
    Ok(())
}

/// Whether the split rule of `level` reads the counts.
pub(super) fn counted(p: &AdaptiveParams, level: u32) -> bool {
    matches!(
        p.split_rule(level),
        SplitRule::Threshold(_) | SplitRule::Share(_)
    )
}

/// scope = global: every pixel x every active quad, in batches that fit one comparison-map buffer
/// (`quad_count` None: the GPU's own count, which always fits).
fn count_dense(
    fx: &Frame,
    timer: &mut StageTimer,
    level: u32,
    lv: &wgpu::Buffer,
    cur: usize,
    quad_count: Option<u32>,
) -> Result<()> {
    let b = fx.b;
    match quad_count {
        Some(q) if q > b.shape.count_quads => {
            for first in (0..q).step_by(b.shape.count_quads as usize) {
                let n = b.shape.count_quads.min(q - first);
                count_batch(fx, timer, &fx.uniform(level, n, first), cur, n, false)?;
            }
            Ok(())
        }
        // GPU-driven: the previous subdivide wrote quad_count's dispatch size (flag words x quads).
        q => count_batch(fx, timer, lv, cur, q.unwrap_or(1), level > 0),
    }
}

fn count_batch(
    fx: &Frame,
    timer: &mut StageTimer,
    uniform: &wgpu::Buffer,
    cur: usize,
    n: u32,
    indirect: bool,
) -> Result<()> {
    let (b, passes, ctx) = (fx.b, fx.passes, fx.fg.ctx);
    let lv = &fx.level(uniform, cur);
    timer.stage(ctx, Stage::REPROJECT_COUNT, |enc| {
        passes.reproject_count.record_dense_bands(
            ctx,
            enc,
            lv,
            &fx.fg.geometry_tiles,
            &b.masks,
            &b.counts,
        );
        Ok(())
    })?;
    timer.stage(ctx, Stage::NEIGHBOURHOOD, |enc| {
        passes
            .neighbourhood
            .record_dense(ctx, enc, lv, &b.counts, &b.low);
        Ok(())
    })?;
    timer.stage(ctx, Stage::QUAD_COUNT, |enc| {
        passes.quad_count.record(
            ctx,
            enc,
            lv,
            &b.low,
            n,
            indirect.then_some(&b.decisions.dispatch_args),
        );
        Ok(())
    })
}

/// scope = local: probes (level > 0), then the level's (pixel, quad) items: their corners'
/// tests, counts and (before the last level) low-quality flags and per-quad counters.
/// `quad_count`: the level's quads where the host knows them (the clears cover only those), None
/// under the GPU-steered loop (they cover the buffers).
fn count_items(
    fx: &Frame,
    timer: &mut StageTimer,
    level: u32,
    lv: &Level,
    quad_count: Option<u32>,
    maps: [&wgpu::TextureView; 2],
) -> Result<()> {
    let (b, passes, ctx) = (fx.b, fx.passes, fx.fg.ctx);
    let (uniform, cur) = (lv.uniform, lv.cur);
    let last = level == fx.p.max_level;
    let (quads, items) = (&b.quads[cur], &b.items);
    if level > 0 {
        // Uniform pixels of last level's split quads test the new samples (the blind-spot fix).
        timer.stage(ctx, Stage::PROBE, |enc| {
            passes
                .probe
                .record_begin(ctx, enc, uniform, &b.control, items);
            Ok(())
        })?;
        timer.stage(ctx, Stage::SHADOW_TEST, |enc| {
            passes.shadow_test.record_probes(
                ctx,
                enc,
                &fx.test_frame(),
                &LocalWork { quads, items, maps },
            );
            Ok(())
        })?;
        timer.stage(ctx, Stage::PROBE, |enc| {
            passes.probe.record(ctx, enc, lv, &b.masks, items);
            Ok(())
        })?;
    }
    timer.stage(ctx, Stage::REPROJECT_COUNT, |enc| {
        // The items compact (and probe) appended become this level's work.
        passes
            .reproject_count
            .record_begin(ctx, enc, uniform, &b.control, items);
        // Only this level's quads: the buffers are sized for 256. The last level writes none.
        if !last {
            enc.clear_buffer(
                &b.counts.maps,
                0,
                quad_count.map(|q| b.shape.counts_bytes_per_quad() * q as u64),
            );
        }
        Ok(())
    })?;
    timer.stage(ctx, Stage::SHADOW_TEST, |enc| {
        passes.shadow_test.record_list(
            ctx,
            enc,
            &fx.test_frame(),
            &LocalWork { quads, items, maps },
            cur,
        );
        Ok(())
    })?;
    timer.stage(ctx, Stage::REPROJECT_COUNT, |enc| {
        if last {
            passes
                .reproject_count
                .record_last(ctx, enc, lv, &b.masks, items);
        } else {
            passes
                .reproject_count
                .record_list(ctx, enc, lv, &b.masks, items, &b.counts);
        }
        Ok(())
    })?;
    // neighbourhood's list also counts each quad's low-quality pixels: no quad_count pass.
    if !last {
        timer.stage(ctx, Stage::NEIGHBOURHOOD, |enc| {
            enc.clear_buffer(
                &b.low.flags,
                0,
                quad_count.map(|q| b.shape.flags_bytes_per_quad() * q as u64),
            );
            passes
                .neighbourhood
                .record_list(ctx, enc, lv, &b.counts, items, &b.low);
            Ok(())
        })?;
    }
    Ok(())
}

fn subdivide(
    fx: &Frame,
    timer: &mut StageTimer,
    lv: &wgpu::Buffer,
    cur: usize,
    nxt: usize,
) -> Result<()> {
    let (fg, b, passes) = (fx.fg, fx.b, fx.passes);
    timer.stage(fg.ctx, Stage::SUBDIVIDE, |enc| {
        passes.subdivide.record(
            fg.ctx,
            enc,
            &fx.level(lv, cur),
            &b.low,
            &b.quads[nxt],
            &b.decisions,
        );
        Ok(())
    })
}

/// scope = local, before the last level: the next level's items and probes, the uniform shares of
/// unrefined quads, and (scissor or cull) the new samples' texel rectangles and culling tiles.
fn compact(
    fx: &Frame,
    timer: &mut StageTimer,
    level: u32,
    lv: &wgpu::Buffer,
    cur: usize,
    nxt: usize,
) -> Result<()> {
    let (fg, b, passes, ctx) = (fx.fg, fx.b, fx.passes, fx.fg.ctx);
    let grow_rects = grows_rects(fx);
    if grow_rects {
        let init: Vec<[u32; 4]> = vec![[u32::MAX, u32::MAX, 0, 0]; LATTICE_POINTS as usize];
        ctx.queue
            .write_buffer(&b.footprints.rects, 0, bytemuck::cast_slice(&init));
    }
    timer.stage(ctx, Stage::COMPACT, |enc| {
        // compact grows the tiles of the next level's new samples only, all of them among its
        // candidates: clear those (a twentieth to three quarters of the 289 samples' tiles).
        if fx.cull.is_some() {
            let bytes = CULL_TILE_WORDS as u64 * 4;
            for k in candidates(level + 1) {
                enc.clear_buffer(&b.footprints.tiles, k as u64 * bytes, Some(bytes));
            }
        }
        let level = fx.level(lv, cur);
        let inputs = CompactInputs {
            counts: &b.counts,
            decisions: &b.decisions,
            next_quads: &b.quads[nxt],
            samples: &b.samples,
            items: &b.items,
            footprints: &b.footprints,
        };
        passes
            .compact
            .record_main(ctx, enc, &level, &fg.gbuffer, &inputs, grow_rects);
        Ok(())
    })
}

/// compact grows each sample's texel rectangle for the scissor and for culling.
fn grows_rects(fx: &Frame) -> bool {
    fx.p.scissor || fx.cull.is_some()
}

/// The host-steered loop's state: it reads each level back and renders exactly what was requested.
struct Waiting<'a> {
    store: &'a mut MapStore,
    samples: &'a mut [GpuSample],
    /// Tests: every map and each level's masks (and consulted samples) into the trace.
    keep: bool,
    trace: AdaptiveTrace,
    /// The samples this level renders, its quad count, and (scissor) the rectangles they serve.
    new: Vec<u32>,
    quad_count: u32,
    rects: Option<Vec<[u32; 4]>>,
    syncs: u32,
    bar: Box<dyn crate::progress::Bar>,
    /// Where an overflow of the item list leaves what its level appended (the method grows the list).
    growth: &'a mut super::growth::Growth,
}

impl<'a> Waiting<'a> {
    fn new(
        fx: &Frame,
        store: &'a mut MapStore,
        samples: &'a mut [GpuSample],
        growth: &'a mut super::growth::Growth,
        keep: bool,
    ) -> Self {
        let bar = crate::progress::bar(fx.p.max_level as u64 + 1, "adaptive levels");
        Waiting {
            store,
            samples,
            keep,
            trace: AdaptiveTrace::default(),
            new: CORNERS.to_vec(),
            quad_count: 1,
            rects: None,
            syncs: 0,
            bar,
            growth,
        }
    }
}

impl Steering for Waiting<'_> {
    fn uniform(&mut self, fx: &Frame, level: u32) -> wgpu::Buffer {
        fx.uniform(level, self.quad_count, 0)
    }

    fn new_maps(
        &mut self,
        fx: &Frame,
        timer: &mut StageTimer,
        _level: u32,
        _lv: &wgpu::Buffer,
    ) -> Result<()> {
        // Level 0's corners precede every rectangle: no scissor.
        render_new(
            fx,
            timer,
            self.store,
            self.samples,
            NewMaps {
                new: &self.new,
                rects: self.rects.as_deref(),
            },
            &mut self.trace,
            self.keep,
        )?;
        // Queue writes: they land before the level's next submission, after the maps' tests.
        let (ctx, b) = (fx.fg.ctx, fx.b);
        ctx.queue.write_buffer(&b.control, 0, &[0u8; 8]);
        if fx.local {
            ctx.queue.write_buffer(
                &b.control,
                std::mem::offset_of!(GpuControl, lookups) as u64,
                &[0u8; 4],
            );
        }
        ctx.queue
            .write_buffer(&b.low.per_quad, 0, &[0u8; QUAD_CAPACITY as usize * 4]);
        Ok(())
    }

    fn quad_count(&self) -> Option<u32> {
        Some(self.quad_count)
    }

    fn maps(&self) -> [&wgpu::TextureView; 2] {
        self.store.views()
    }

    fn end_level(
        &mut self,
        fx: &Frame,
        timer: &mut StageTimer,
        level: u32,
        _lv: &wgpu::Buffer,
        evaluated: bool,
    ) -> Result<bool> {
        let (fg, b, local) = (fx.fg, fx.b, fx.local);
        // The one read-back of this level.
        timer.flush(fg.ctx);
        let pictures =
            fx.pictures && evaluated && (local || self.quad_count <= b.shape.count_quads);
        let quads = self
            .trace
            .levels
            .last()
            .map_or_else(|| vec![ROOT], |r: &LevelReport| r.next_quads.clone());
        let nxt = 1 - (level % 2) as usize;
        let kept = fx.cull.map(|c| &c.1);
        let keep = self.keep;
        let report = timer.cpu(Stage::READBACK_LEVEL, || {
            let r = levels::LevelRead {
                n: quads.len() as u64,
                kept: kept.is_some(),
                pictures: pictures || keep,
                intermediates: keep,
                local,
            };
            let of = levels::LevelOf {
                level,
                quads,
                evaluated,
            };
            levels::read_level(fg, b, of, &b.quads[nxt], kept, r)
        })?;
        self.syncs += 1;
        if let Some(e) = report.overflow_error(level) {
            if report.item_overflow() {
                self.growth.overflowed(report.appended as u64, self.syncs);
            }
            self.bar.finish_and_clear();
            return Err(e);
        }
        self.rects = if local && fx.p.scissor {
            Some(report.rects.clone())
        } else {
            None
        };
        self.new = report.new_samples.clone();
        self.quad_count = report.next_quad_count;
        self.trace.levels.push(report);
        self.bar.inc(1);
        Ok(self.quad_count != 0)
    }
}

/// A host-steered frame of either scope (steer = cpu, or a setting the GPU cannot steer).
/// `keep` reads back every intermediate buffer (maps, masks, comparison maps) for twin tests;
/// it adds synchronisations, so it is for tests only.
pub(super) fn run(
    fg: &FrameGpu,
    timer: &mut StageTimer,
    p: &AdaptiveParams,
    prepared: &mut Prepared,
    keep: bool,
    pictures: bool,
) -> Result<(MethodOutput, AdaptiveTrace)> {
    let Prepared {
        b,
        store,
        passes,
        samples,
        cull,
        growth,
        ..
    } = prepared;
    let fx = Frame::new(fg, p, b, passes, cull.as_ref(), pictures);
    fx.begin();
    let mut waiting = Waiting::new(&fx, store, samples, growth, keep);
    if fx.local {
        begin_local(&fx, timer)?;
    }
    levels(&fx, timer, &mut waiting)?;
    // Every level's maps are submitted: what the layers hold is what their keys name.
    waiting.store.slots.commit();
    waiting.bar.finish_and_clear();
    let Waiting {
        mut trace,
        mut syncs,
        store,
        samples,
        ..
    } = waiting;
    let last = trace.levels.last().cloned().unwrap_or_default();
    let whole = fg.scene_gpu.index_count as u64 / 3;
    trace.triangles = match fx.passes.culled_maps.as_ref() {
        // The counts the GPU wrote (scope = global): one read-back after the last level.
        Some(c) => {
            timer.flush(fg.ctx);
            syncs += 1;
            timer.cpu(Stage::READBACK, || c.triangles(fg, &trace.rendered))?
        }
        None => trace
            .rendered
            .iter()
            .map(|&k| {
                if trace.culled.contains(&k) {
                    last.triangles[k as usize] as u64 / 3
                } else {
                    whole
                }
            })
            .collect(),
    };
    trace.weights = sample_weights(p, &trace.levels, &last.sample_level, &trace.rendered);
    trace.samples = samples.to_vec();
    let consulted = if fx.local {
        end_local(&fx, timer)?
    } else {
        end_global(&fx, timer, &trace.weights)?
    };
    let out = output(&fx, &trace, syncs, store, consulted.as_deref())?;
    Ok((out, trace))
}

/// scope = local before level 0: every geometry pixel becomes an item of the root, and (cull) the
/// corners' tiles take an infinite limit, so their cull drops only what can change no texel
/// (triangles that cover no texel centre, back faces).
pub(super) fn begin_local(fx: &Frame, timer: &mut StageTimer) -> Result<()> {
    let (fg, b, ctx) = (fx.fg, fx.b, fx.fg.ctx);
    let level = fx.uniform(0, 1, 0);
    timer.stage(ctx, Stage::COMPACT, |enc| {
        fx.passes
            .compact
            .record_seed(ctx, enc, &fg.screen(), &level, &b.control, &b.items);
        Ok(())
    })?;
    if fx.cull.is_some() {
        let every = vec![f32::INFINITY.to_bits(); CULL_TILE_WORDS as usize];
        for k in CORNERS {
            ctx.queue.write_buffer(
                &b.footprints.tiles,
                k as u64 * CULL_TILE_WORDS as u64 * 4,
                bytemuck::cast_slice(&every),
            );
        }
    }
    Ok(())
}

/// scope = global after the last level: V from the masks and the weights (written by the host).
fn end_global(fx: &Frame, timer: &mut StageTimer, weights: &[f32]) -> Result<Option<Vec<u32>>> {
    fx.fg
        .ctx
        .queue
        .write_buffer(&fx.b.weights, 0, bytemuck::cast_slice(weights));
    shade(fx, timer)?;
    Ok(None)
}

/// V = Σ ŵ_k lit_k from each pixel's lattice mask (scope = global).
pub(super) fn shade(fx: &Frame, timer: &mut StageTimer) -> Result<()> {
    let (fg, b, ctx) = (fx.fg, fx.b, fx.fg.ctx);
    timer.stage(ctx, Stage::SHADE, |enc| {
        fg.shade
            .record_masks(ctx, enc, &fg.screen(), &b.weights, &b.masks.lit);
        Ok(())
    })
}

/// scope = local after the last level: V from the integer sums.
pub(super) fn resolve_local(fx: &Frame, timer: &mut StageTimer) -> Result<()> {
    let (fg, b, ctx) = (fx.fg, fx.b, fx.fg.ctx);
    let lv = fx.uniform(fx.p.max_level, 0, 0);
    // compact's `resolve` entry point: its time is compact's (no shade pass runs under local scope).
    timer.stage(ctx, Stage::COMPACT, |enc| {
        fx.passes
            .compact
            .record_resolve(ctx, enc, &fg.screen(), &lv, &b.items);
        Ok(())
    })
}

/// scope = local after the last level: V, and with pictures the samples each pixel consulted.
fn end_local(fx: &Frame, timer: &mut StageTimer) -> Result<Option<Vec<u32>>> {
    let (fg, b, ctx) = (fx.fg, fx.b, fx.fg.ctx);
    resolve_local(fx, timer)?;
    if !fx.pictures {
        return Ok(None);
    }
    timer.flush(ctx);
    let bytes = fg.gbuffer.width as u64 * fg.gbuffer.height as u64 * 40;
    Ok(Some(timer.cpu(Stage::PICTURES, || {
        readback::read_buffer(ctx, &b.masks.consulted, bytes)
    })?))
}

/// The method's output of a host-steered frame: pictures and the record.
fn output(
    fx: &Frame,
    trace: &AdaptiveTrace,
    syncs: u32,
    store: &MapStore,
    consulted: Option<&[u32]>,
) -> Result<MethodOutput> {
    let fg = fx.fg;
    let pictures = if fx.pictures {
        pictures::all(fg, trace, consulted)
    } else {
        Vec::new()
    };
    // The hybrid store's allocation read-backs are syncs the representation needs.
    let syncs = syncs + store.hybrid.as_ref().map_or(0, |h| h.stats.syncs);
    let mut record = levels::record(fx.p, trace, syncs, consulted, &fg.gbuffer);
    record.hybrid = store.hybrid.as_ref().map(|h| h.record());
    // A point light's lattice sample is its cube's six maps.
    let maps = trace.rendered.len() as u32 * super::faces_per_sample(&trace.samples).max(1);
    Ok(MethodOutput {
        shadow_maps: maps,
        syncs,
        record: record.to_value()?,
        pictures,
        bound: None,
    })
}

/// The uniform of one level (a batch of `quad_count` quads from `first_quad` in dense mode) on
/// buffers of `shape`; tests and benches build it to drive a count pass alone.
pub fn level_uniform(
    p: &AdaptiveParams,
    shape: Shape,
    level: u32,
    quad_count: u32,
    first_quad: u32,
) -> GpuLevel {
    let (split_mode, split_threshold, split_share) = match p.split_rule(level) {
        SplitRule::Threshold(t) => (SPLIT_THRESHOLD, t, 0.0),
        SplitRule::Always => (SPLIT_ALWAYS, 0, 0.0),
        SplitRule::Never => (SPLIT_NEVER, 0, 0.0),
        SplitRule::Share(s) => (SPLIT_SHARE, 0, s),
    };
    GpuLevel {
        level,
        max_level: p.max_level,
        quad_count,
        first_quad,
        split_threshold,
        split_mode,
        split_share,
        words_per_row: shape.words_per_row,
        flag_words_per_row: shape.flag_words_per_row,
        item_capacity: shape.item_capacity,
        work_count: 0,
        dense_groups_x: groups(shape.height * shape.flag_words_per_row, LINE_WORKGROUP[0]),
        quad_capacity: QUAD_CAPACITY,
        hold: p.hold,
        pad0: 0,
        ..Default::default()
    }
}
