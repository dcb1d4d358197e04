//! The GPU-steered level loop (scope = global on the corner-to-corner lattice, and scope = local
//! without scissor or cull; docs/gpu-frame.md).
//! Every level is recorded up front and the GPU's decisions drive the next level without a
//! read-back:
//! - each level rasterizes every sample it could need (its candidates: the points of its grid
//!   not on the coarser one), with draw_indexed_indirect arguments whose instance count is copied
//!   from the sample's request flag, which subdivide sets: 0 draws nothing;
//! - shadow_test lists the candidates and skips those not requested;
//! - each level's uniform takes its quad count from the previous subdivide by a buffer copy, and
//!   quad_count dispatches indirectly, as subdivide sizes it, and neighbourhood loops over the
//!   uniform's quads;
//! - the weights pass computes ŵ from the leaves and the rendered samples; shade follows.
//!
//! Under scope = local every map stays alive, so each candidate of every level has its own layer
//! across the store's two arrays; the item passes already dispatch indirectly, and compact's
//! `resolve` ends the frame.
//!
//! Each level's record is copied aside on the GPU and read after the frame (`finish`).

use super::context::Frame;
use super::frame::{self, Steering};
use super::levels::{self, LevelRead};
use super::maps::MapStore;
use super::{candidates, pictures, AdaptiveTrace, Prepared, ROOT};
use crate::gpu::readback;
use crate::gpu::structs::GpuControl;
use crate::gpu::structs::GpuSample;
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::methods::adaptive::buffers::{AdaptiveBuffers, LATTICE_POINTS};
use crate::methods::{AdaptiveParams, MethodOutput, Scope, Weights};
use crate::render::shadow_raster::{RasterJob, ShadowMapArray};
use crate::stages::raster::RasterTarget;
use crate::stages::weights::{WeightsPass, RULE_AREA, RULE_COONS, RULE_LEVEL};
use crate::stages::FrameGpu;
use crate::Result;

/// u32 words of one draw_indexed_indirect argument set.
const ARGS_WORDS: u64 = 5;

/// Whether the GPU can steer this setting, unless `steer = cpu`: global scope on the
/// corner-to-corner lattice (the GPU weights cover its rules) where every level's quads fit one
/// batch of comparison maps; local scope without scissor or cull (compact grows their rectangles
/// and tiles for the host's list of new maps).
pub(crate) fn eligible(p: &AdaptiveParams, b: &AdaptiveBuffers) -> bool {
    let most_quads = 1u32 << (2 * p.max_level.saturating_sub(1));
    !p.steer_cpu
        && match p.scope {
            Scope::Global => p.border_strip() == 0.0 && b.shape.count_quads >= most_quads,
            Scope::Local => !p.scissor && p.cull != Some(true),
        }
}

/// Built once with the method: the weights pass, the raster arguments and the record buffer.
pub(crate) struct Steer {
    weights: WeightsPass,
    /// ARGS_WORDS per lattice sample: whole-mesh indexed draw, first instance = the sample.
    raster_args: wgpu::Buffer,
    /// Each level's record (levels::level_parts), then the weights; read after the frame.
    history: wgpu::Buffer,
}

/// What `finish` needs of one steered frame.
pub(crate) struct Pending {
    /// Per level: the record's layout, whether it was counted, its byte offset in the history.
    reads: Vec<(LevelRead, bool, u64)>,
    weights_at: u64,
    /// The frame asked for pictures: `finish` draws them from the records.
    pictures: bool,
}

fn level_read(pictures: bool, level: u32, evaluate: bool, local: bool) -> LevelRead {
    // Pictures need level 0's comparison map and flags (one quad); deeper levels' flags are left out.
    LevelRead {
        n: 1,
        kept: false,
        pictures: pictures && level == 0 && evaluate,
        intermediates: false,
        local,
    }
}

/// One level's record: what the waiting loop reads back, with the next level's quads.
fn record_parts(b: &AdaptiveBuffers, read: LevelRead) -> Vec<(&wgpu::Buffer, u64)> {
    levels::level_parts(b, &b.quads[0], None, read)
}

impl Steer {
    pub(crate) fn new(fg: &FrameGpu, p: &AdaptiveParams, b: &AdaptiveBuffers) -> Result<Self> {
        let ctx = fg.ctx;
        let rule = match p.weights {
            Weights::Level => RULE_LEVEL,
            Weights::Area => RULE_AREA,
            Weights::Coons => RULE_COONS,
        };
        // Every level's record (with pictures: an upper bound), then the weights.
        let level_bytes: u64 = record_parts(b, level_read(true, 0, true, p.scope == Scope::Local))
            .iter()
            .map(|(_, s)| s)
            .sum();
        let bytes = level_bytes * (p.max_level as u64 + 1) + LATTICE_POINTS as u64 * 4;
        Ok(Self {
            weights: WeightsPass::new(ctx, rule)?,
            raster_args: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("steered raster arguments"),
                size: LATTICE_POINTS as u64 * ARGS_WORDS * 4,
                usage: wgpu::BufferUsages::INDIRECT
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            }),
            history: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("level records"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        })
    }
}

/// The GPU-steered loop's state: each level renders all its candidates, drawing and testing only
/// those subdivide requested, and copies its record aside.
struct Steered<'a> {
    steer: &'a Steer,
    store: &'a MapStore,
    per_array: usize,
    samples: &'a [GpuSample],
    reads: Vec<(LevelRead, bool, u64)>,
    history_at: u64,
}

impl Steered<'_> {
    /// The candidates of `chunk` (all in `array`) drawn whole, each with its request flag as the
    /// instance count (the compute raster rasterizes them all).
    fn record_flagged(
        &self,
        fx: &Frame,
        enc: &mut wgpu::CommandEncoder,
        level: u32,
        chunk: &[u32],
        array: &ShadowMapArray,
    ) -> Result<()> {
        let (fg, b) = (fx.fg, fx.b);
        let mut jobs = Vec::with_capacity(chunk.len());
        for &k in chunk {
            let at = k as u64 * ARGS_WORDS * 4;
            if level > 0 {
                // instance count ← the request flag subdivide set (0 or 1).
                enc.copy_buffer_to_buffer(
                    &b.decisions.lattice_state,
                    k as u64 * 4,
                    &self.steer.raster_args,
                    at + 4,
                    4,
                );
            }
            jobs.push((
                RasterJob {
                    sample: k,
                    layer: self.samples[k as usize].layer,
                    scissor: None,
                },
                at,
            ));
        }
        fg.raster.record_flagged(
            fx.fg.ctx,
            enc,
            &RasterTarget {
                scene: &fg.scene_gpu,
                samples: &b.samples,
                array,
            },
            &jobs,
            &self.steer.raster_args,
        )
    }

    /// scope = local: the level's requested maps into their own layers (kept for the rest of the
    /// frame), then the level's counters cleared, as the waiting loop's queue writes do.
    fn new_maps_local(
        &mut self,
        fx: &Frame,
        timer: &mut StageTimer,
        level: u32,
        lv: &wgpu::Buffer,
    ) -> Result<()> {
        let (fg, b, ctx) = (fx.fg, fx.b, fx.fg.ctx);
        let cand = candidates(level);
        let array_of = |k: u32| self.samples[k as usize].array as usize;
        let one_array = cand.iter().all(|&k| array_of(k) == array_of(cand[0]));
        timer.stage(ctx, fg.raster.stage(), |enc| {
            if level > 0 {
                // GpuLevel.quad_count (byte 8) ← control.next_quad_count of the previous level.
                enc.copy_buffer_to_buffer(&b.control, 0, lv, 8, 4);
            }
            if level > 0 && one_array && fg.raster.is_compute() {
                let array = &self.store.arrays[array_of(cand[0])];
                fg.raster.record_requested(
                    ctx,
                    enc,
                    &RasterTarget {
                        scene: &fg.scene_gpu,
                        samples: &b.samples,
                        array,
                    },
                    (&b.control, &b.decisions.new_samples),
                    cand.len() as u32,
                )?;
            } else {
                for (a, array) in self.store.arrays.iter().enumerate() {
                    let mine: Vec<u32> =
                        cand.iter().copied().filter(|&k| array_of(k) == a).collect();
                    if !mine.is_empty() {
                        self.record_flagged(fx, enc, level, &mine, array)?;
                    }
                }
            }
            // The level's counters, after the raster read the request count.
            enc.clear_buffer(&b.control, 0, Some(8));
            enc.clear_buffer(
                &b.control,
                std::mem::offset_of!(GpuControl, lookups) as u64,
                Some(4),
            );
            enc.clear_buffer(&b.low.per_quad, 0, None);
            Ok(())
        })
    }
}

impl Steering for Steered<'_> {
    fn uniform(&mut self, fx: &Frame, level: u32) -> wgpu::Buffer {
        // Level 0 has the root; deeper levels take the previous subdivide's count (copied in new_maps).
        fx.uniform(level, (level == 0) as u32, 0)
    }

    fn new_maps(
        &mut self,
        fx: &Frame,
        timer: &mut StageTimer,
        level: u32,
        lv: &wgpu::Buffer,
    ) -> Result<()> {
        if fx.local {
            return self.new_maps_local(fx, timer, level, lv);
        }
        let (fg, b, ctx) = (fx.fg, fx.b, fx.fg.ctx);
        let (steer, array, per_array) = (self.steer, &self.store.arrays[0], self.per_array);
        let cand = candidates(level);
        let chunks = cand.len().div_ceil(per_array);
        // The compute raster rasterizes only what subdivide requested, in one chunk of layers.
        let requested_only = level > 0 && chunks == 1 && fg.raster.is_compute();
        for (c, chunk) in cand.chunks(per_array).enumerate() {
            timer.stage(ctx, fg.raster.stage(), |enc| {
                if level == 0 && c == 0 {
                    steer.weights.record_begin(enc);
                }
                if level > 0 && c == 0 {
                    // GpuLevel.quad_count (byte 8) ← control.next_quad_count of the previous level.
                    enc.copy_buffer_to_buffer(&b.control, 0, lv, 8, 4);
                }
                if requested_only {
                    return fg.raster.record_requested(
                        ctx,
                        enc,
                        &RasterTarget {
                            scene: &fg.scene_gpu,
                            samples: &b.samples,
                            array,
                        },
                        (&b.control, &b.decisions.new_samples),
                        cand.len() as u32,
                    );
                }
                self.record_flagged(fx, enc, level, chunk, array)
            })?;
            timer.stage(ctx, Stage::SHADOW_TEST, |enc| {
                if level > 0 && cand.len() <= per_array {
                    // One chunk: test only what subdivide requested (its list and count).
                    fx.passes.shadow_test.record_requested(
                        ctx,
                        enc,
                        &fx.test_frame(),
                        &array.array_view,
                        cand.len() as u32,
                    );
                } else {
                    fx.passes.shadow_test.record(
                        ctx,
                        enc,
                        &fx.test_frame(),
                        &array.array_view,
                        chunk,
                    );
                }
                if c + 1 == chunks {
                    // The level's counters, after the test read the request count.
                    enc.clear_buffer(&b.control, 0, Some(8));
                    enc.clear_buffer(&b.low.per_quad, 0, None);
                }
                Ok(())
            })?;
        }
        Ok(())
    }

    fn quad_count(&self) -> Option<u32> {
        None
    }

    fn maps(&self) -> [&wgpu::TextureView; 2] {
        self.store.views()
    }

    fn end_level(
        &mut self,
        fx: &Frame,
        timer: &mut StageTimer,
        level: u32,
        lv: &wgpu::Buffer,
        evaluated: bool,
    ) -> Result<bool> {
        let (fg, b) = (fx.fg, fx.b);
        let read = level_read(fx.pictures, level, evaluated, fx.local);
        self.reads.push((read, evaluated, self.history_at));
        let cur = (level % 2) as usize;
        timer.stage(fg.ctx, Stage::WEIGHTS, |enc| {
            for (buf, size) in levels::level_parts(b, &b.quads[1 - cur], None, read) {
                enc.copy_buffer_to_buffer(buf, 0, &self.steer.history, self.history_at, size);
                self.history_at += size;
            }
            // scope = local sums each pixel's own quads: it needs no weights.
            if !fx.local {
                self.steer
                    .weights
                    .record_leaves(fg.ctx, enc, lv, &b.quads[cur], &b.decisions);
            }
            Ok(())
        })?;
        // Every level is recorded: a level with no quads left does nothing.
        Ok(true)
    }
}

/// Records the whole frame; nothing waits (in stages mode the timer still waits per stage).
pub(crate) fn run(
    fg: &FrameGpu,
    timer: &mut StageTimer,
    p: &AdaptiveParams,
    prepared: &mut Prepared,
    pictures: bool,
) -> Result<(MethodOutput, Pending)> {
    let ctx = fg.ctx;
    let Prepared {
        b,
        store,
        passes,
        samples,
        steer,
        ..
    } = prepared;
    let steer = steer.as_ref().expect("steered run without its state");
    let per_array = store.per_array as usize;

    // Before the frame's commands (queue writes land first): every candidate's layer is its place
    // in its level's chunk, the draws are the whole mesh with no instance but the corners', and
    // the counters, root quad and corner requests start the frame.
    // Under scope = local each candidate keeps its own layer: the store's slots in level order.
    let local = p.scope == Scope::Local;
    let mut slot = 0;
    let mut args = vec![0u32; (LATTICE_POINTS as u64 * ARGS_WORDS) as usize];
    for level in 0..=p.max_level {
        for (n, &k) in candidates(level).iter().enumerate() {
            let (array, layer) = if local {
                (slot / per_array, slot % per_array)
            } else {
                (0, n % per_array)
            };
            slot += 1;
            samples[k as usize].layer = layer as u32;
            samples[k as usize].array = array as u32;
            let a = &mut args[k as usize * ARGS_WORDS as usize..][..ARGS_WORDS as usize];
            a.copy_from_slice(&[fg.scene_gpu.index_count, (level == 0) as u32, 0, 0, k]);
        }
    }
    ctx.queue
        .write_buffer(&b.samples, 0, bytemuck::cast_slice(samples));
    ctx.queue
        .write_buffer(&steer.raster_args, 0, bytemuck::cast_slice(&args));
    let fx = Frame::new(fg, p, b, passes, None, pictures);
    fx.begin();
    if local {
        frame::begin_local(&fx, timer)?;
    }
    let mut steered = Steered {
        steer,
        store,
        per_array,
        samples,
        reads: Vec::new(),
        history_at: 0,
    };
    frame::levels(&fx, timer, &mut steered)?;
    let weights_at = steered.history_at;
    if local {
        // V from the integer sums; the pictures' consulted samples are read in `finish`.
        frame::resolve_local(&fx, timer)?;
    } else {
        timer.stage(ctx, Stage::WEIGHTS, |enc| {
            steer.weights.record(ctx, enc, &b.decisions, &b.weights);
            enc.copy_buffer_to_buffer(
                &b.weights,
                0,
                &steer.history,
                weights_at,
                LATTICE_POINTS as u64 * 4,
            );
            Ok(())
        })?;
        frame::shade(&fx, timer)?;
    }
    // shadow_maps and the record come in `finish`, after the frame.
    let out = MethodOutput {
        shadow_maps: 0,
        syncs: 0,
        record: serde_json::Value::Null,
        pictures: Vec::new(),
        bound: None,
    };
    Ok((
        out,
        Pending {
            reads: steered.reads,
            weights_at,
            pictures,
        },
    ))
}

/// After the frame: reads the level records and the weights (one read-back, outside the frame's
/// clock) and fills in what the waiting loop reports.
pub(crate) fn finish(
    fg: &FrameGpu,
    p: &AdaptiveParams,
    prepared: &mut Prepared,
    pending: Pending,
    out: &mut MethodOutput,
) -> Result<AdaptiveTrace> {
    let steer = prepared
        .steer
        .as_ref()
        .expect("steered frame without its state");
    let words: Vec<u32> = readback::map_staging(fg.ctx, &steer.history)?;
    let mut trace = AdaptiveTrace::default();
    let mut quads = vec![ROOT];
    trace.rendered = candidates(0);
    for (level, &(read, evaluated, at)) in pending.reads.iter().enumerate() {
        let read = LevelRead {
            n: quads.len() as u64,
            ..read
        };
        let report = levels::parse_level(
            &prepared.b,
            &words[(at / 4) as usize..],
            levels::LevelOf {
                level: level as u32,
                quads,
                evaluated,
            },
            read,
        );
        if let Some(e) = report.overflow_error(level as u32) {
            // The frame ran to its end: V's read-back and this one are what it cost.
            if report.item_overflow() {
                prepared.growth.overflowed(report.appended as u64, 2);
            }
            return Err(e);
        }
        quads = report.next_quads.clone();
        let done = report.next_quad_count == 0;
        trace.rendered.extend_from_slice(&report.new_samples);
        trace.levels.push(report);
        if done {
            break;
        }
    }
    let local = p.scope == Scope::Local;
    trace.weights = if local {
        let last = trace.levels.last().cloned().unwrap_or_default();
        super::sample_weights(p, &trace.levels, &last.sample_level, &trace.rendered)
    } else {
        let w = (pending.weights_at / 4) as usize;
        bytemuck::cast_slice::<u32, f32>(&words[w..w + LATTICE_POINTS as usize]).to_vec()
    };
    trace.samples = prepared.samples.clone();
    trace.triangles = vec![fg.scene_gpu.index_count as u64 / 3; trace.rendered.len()];
    // scope = local's pictures show the samples each pixel consulted: read after the frame too.
    let consulted = if local && pending.pictures {
        let bytes = fg.gbuffer.width as u64 * fg.gbuffer.height as u64 * 40;
        Some(readback::read_buffer::<u32>(
            fg.ctx,
            &prepared.b.masks.consulted,
            bytes,
        )?)
    } else {
        None
    };
    out.shadow_maps = trace.rendered.len() as u32;
    out.syncs = 0;
    let mut record = levels::record(p, &trace, 0, consulted.as_deref(), &fg.gbuffer);
    record.steer = Some("gpu: no read-back in the frame; the level records are read after it");
    // What each level rasterized past level 0 (new_maps' `requested_only`).
    let one_chunk = (1..=p.max_level).all(|l| {
        let arrays: std::collections::BTreeSet<u32> = candidates(l)
            .iter()
            .map(|&k| prepared.samples[k as usize].array)
            .collect();
        candidates(l).len() <= prepared.store.per_array as usize && arrays.len() == 1
    });
    record.steer_raster = Some(if fg.raster.is_compute() && one_chunk {
        "compute: only the maps subdivide requested, dispatches sized on the GPU"
    } else {
        "every candidate layer cleared, drawn with the request flag as instance count"
    });
    out.record = record.to_value()?;
    out.pictures = if pending.pictures {
        pictures::all(fg, &trace, consulted.as_deref())
    } else {
        Vec::new()
    };
    Ok(trace)
}
