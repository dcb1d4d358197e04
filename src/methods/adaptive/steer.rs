//! The GPU-steered level loop (scope = global, corner-to-corner lattice; docs/gpu-frame.md).
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
//! Each level's record is copied aside on the GPU and read after the frame (`finish`).

use crate::gpu::Stage;
use super::context::Frame;
use super::frame::{self, Steering};
use super::levels::{self, LevelRead};
use super::{candidates, pictures, AdaptiveTrace, Prepared, ROOT};
use crate::gpu::readback;
use crate::gpu::structs::GpuSample;
use crate::gpu::timing::StageTimer;
use crate::methods::adaptive::buffers::{AdaptiveBuffers, LATTICE_POINTS};
use crate::methods::{AdaptiveParams, MethodOutput, Scope, Weights};
use crate::render::shadow_raster::{RasterJob, ShadowMapArray};
use crate::stages::weights::{WeightsPass, RULE_AREA, RULE_COONS, RULE_LEVEL};
use crate::stages::FrameGpu;
use crate::Result;

/// u32 words of one draw_indexed_indirect argument set.
const ARGS_WORDS: u64 = 5;


/// Whether the GPU can steer this setting: global scope on the corner-to-corner lattice (the GPU
/// weights cover its rules), unless `steer = cpu`, and every level's quads fit one batch of
/// comparison maps.
pub fn eligible(p: &AdaptiveParams, b: &AdaptiveBuffers) -> bool {
    let most_quads = 1u32 << (2 * p.max_level.saturating_sub(1));
    !p.steer_cpu && p.scope == Scope::Global && p.border_strip() == 0.0 && b.shape.count_quads >= most_quads
}

/// Built once with the method: the weights pass, the raster arguments and the record buffer.
pub struct Steer {
    weights: WeightsPass,
    /// ARGS_WORDS per lattice sample: whole-mesh indexed draw, first instance = the sample.
    raster_args: wgpu::Buffer,
    /// Each level's record (levels::level_parts), then the weights; read after the frame.
    history: wgpu::Buffer,
}

/// What `finish` needs of one steered frame.
pub struct Pending {
    /// Per level: the record's layout, whether it was counted, its byte offset in the history.
    reads: Vec<(LevelRead, bool, u64)>,
    weights_at: u64,
    /// The frame asked for pictures: `finish` draws them from the records.
    pictures: bool,
}

fn level_read(pictures: bool, level: u32, evaluate: bool) -> LevelRead {
    // Pictures need level 0's comparison map and flags (one quad); deeper levels' flags are left out.
    LevelRead { n: 1, kept: false, pictures: pictures && level == 0 && evaluate, intermediates: false, local: false }
}

/// One level's record: what the waiting loop reads back, with the next level's quads.
fn record_parts(b: &AdaptiveBuffers, read: LevelRead) -> Vec<(&wgpu::Buffer, u64)> {
    levels::level_parts(b, &b.quads[0], None, read)
}

impl Steer {
    pub fn new(fg: &FrameGpu, p: &AdaptiveParams, b: &AdaptiveBuffers) -> Result<Self> {
        let ctx = fg.ctx;
        let rule = match p.weights {
            Weights::Level => RULE_LEVEL,
            Weights::Area => RULE_AREA,
            Weights::Coons => RULE_COONS,
        };
        // Every level's record (with pictures: an upper bound), then the weights.
        let level_bytes: u64 = record_parts(b, level_read(true, 0, true)).iter().map(|(_, s)| s).sum();
        let bytes = level_bytes * (p.max_level as u64 + 1) + LATTICE_POINTS as u64 * 4;
        Ok(Self {
            weights: WeightsPass::new(ctx, rule)?,
            raster_args: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("steered raster arguments"),
                size: LATTICE_POINTS as u64 * ARGS_WORDS * 4,
                usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::STORAGE,
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
    array: &'a ShadowMapArray,
    per_array: usize,
    samples: &'a [GpuSample],
    reads: Vec<(LevelRead, bool, u64)>,
    history_at: u64,
}

impl Steering for Steered<'_> {
    fn uniform(&mut self, fx: &Frame, level: u32) -> wgpu::Buffer {
        // Level 0 has the root; deeper levels take the previous subdivide's count (copied in new_maps).
        fx.uniform(level, (level == 0) as u32, 0)
    }

    fn new_maps(&mut self, fx: &Frame, timer: &mut StageTimer, level: u32, lv: &wgpu::Buffer) -> Result<()> {
        let (fg, b, ctx) = (fx.fg, fx.b, fx.fg.ctx);
        let (steer, array, per_array) = (self.steer, self.array, self.per_array);
        let cand = candidates(level);
        let chunks = cand.len().div_ceil(per_array);
        // The compute raster rasterizes only what subdivide requested, in one chunk of layers.
        let requested_only = level > 0 && chunks == 1 && fg.raster.is_compute();
        for (c, chunk) in cand.chunks(per_array).enumerate() {
            timer.stage(ctx, Stage::SHADOW_RASTER, |enc| {
                if level == 0 && c == 0 {
                    steer.weights.record_begin(enc);
                }
                if level > 0 && c == 0 {
                    // GpuLevel.quad_count (byte 8) ← control.next_quad_count of the previous level.
                    enc.copy_buffer_to_buffer(&b.control, 0, lv, 8, 4);
                }
                if requested_only {
                    return fg.raster.record_requested(ctx, enc, &fg.scene_gpu, &b.samples, (&b.control, &b.decisions.new_samples), cand.len() as u32, array);
                }
                let mut jobs = Vec::with_capacity(chunk.len());
                for &k in chunk {
                    let at = k as u64 * ARGS_WORDS * 4;
                    if level > 0 {
                        // instance count ← the request flag subdivide set (0 or 1).
                        enc.copy_buffer_to_buffer(&b.decisions.lattice_state, k as u64 * 4, &steer.raster_args, at + 4, 4);
                    }
                    jobs.push((RasterJob { sample: k, layer: self.samples[k as usize].layer, scissor: None }, at));
                }
                fg.raster.record_flagged(ctx, enc, &fg.scene_gpu, &b.samples, array, &jobs, &steer.raster_args)?;
                Ok(())
            })?;
            timer.stage(ctx, Stage::SHADOW_TEST, |enc| {
                if level > 0 && cand.len() <= per_array {
                    // One chunk: test only what subdivide requested (its list and count).
                    fx.passes.shadow_test.record_requested(ctx, enc, &fg.frame_buffer, &fg.gbuffer, &fg.geometry_tiles, b.requests(), &b.masks, &array.array_view, cand.len() as u32);
                } else {
                    fx.passes.shadow_test.record(ctx, enc, &fg.frame_buffer, &fg.gbuffer, &fg.geometry_tiles, b.requests(), &b.masks, &array.array_view, chunk);
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
        [&self.array.array_view, &self.array.array_view]
    }

    fn end_level(&mut self, fx: &Frame, timer: &mut StageTimer, level: u32, lv: &wgpu::Buffer, evaluated: bool) -> Result<bool> {
        let (fg, b) = (fx.fg, fx.b);
        let read = level_read(fx.pictures, level, evaluated);
        self.reads.push((read, evaluated, self.history_at));
        let cur = (level % 2) as usize;
        timer.stage(fg.ctx, Stage::WEIGHTS, |enc| {
            for (buf, size) in levels::level_parts(b, &b.quads[1 - cur], None, read) {
                enc.copy_buffer_to_buffer(buf, 0, &self.steer.history, self.history_at, size);
                self.history_at += size;
            }
            self.steer.weights.record_leaves(fg.ctx, enc, lv, &b.quads[cur], &b.decisions);
            Ok(())
        })?;
        // Every level is recorded: a level with no quads left does nothing.
        Ok(true)
    }
}

/// Records the whole frame; nothing waits (in stages mode the timer still waits per stage).
pub fn run(fg: &FrameGpu, timer: &mut StageTimer, p: &AdaptiveParams, prepared: &mut Prepared, pictures: bool) -> Result<(MethodOutput, Pending)> {
    let ctx = fg.ctx;
    let Prepared { b, store, passes, samples, steer, .. } = prepared;
    let steer = steer.as_ref().expect("steered run without its state");
    let per_array = store.per_array as usize;

    // Before the frame's commands (queue writes land first): every candidate's layer is its place
    // in its level's chunk, the draws are the whole mesh with no instance but the corners', and
    // the counters, root quad and corner requests start the frame.
    let mut args = vec![0u32; (LATTICE_POINTS as u64 * ARGS_WORDS) as usize];
    for level in 0..=p.max_level {
        for (n, &k) in candidates(level).iter().enumerate() {
            samples[k as usize].layer = (n % per_array) as u32;
            samples[k as usize].array = 0;
            let a = &mut args[k as usize * ARGS_WORDS as usize..][..ARGS_WORDS as usize];
            a.copy_from_slice(&[fg.scene_gpu.index_count, (level == 0) as u32, 0, 0, k]);
        }
    }
    ctx.queue.write_buffer(&b.samples, 0, bytemuck::cast_slice(samples));
    ctx.queue.write_buffer(&steer.raster_args, 0, bytemuck::cast_slice(&args));
    let fx = Frame::new(fg, p, b, passes, None, pictures);
    fx.begin();
    let mut steered = Steered { steer, array: &store.arrays[0], per_array, samples, reads: Vec::new(), history_at: 0 };
    frame::levels(&fx, timer, &mut steered)?;
    let weights_at = steered.history_at;
    timer.stage(ctx, Stage::WEIGHTS, |enc| {
        steer.weights.record(ctx, enc, &b.decisions, &b.weights);
        enc.copy_buffer_to_buffer(&b.weights, 0, &steer.history, weights_at, LATTICE_POINTS as u64 * 4);
        Ok(())
    })?;
    frame::shade(&fx, timer)?;
    // shadow_maps and the record come in `finish`, after the frame.
    let out = MethodOutput { shadow_maps: 0, syncs: 0, record: serde_json::Value::Null, pictures: Vec::new() };
    Ok((out, Pending { reads: steered.reads, weights_at, pictures }))
}

/// After the frame: reads the level records and the weights (one read-back, outside the frame's
/// clock) and fills in what the waiting loop reports.
pub fn finish(fg: &FrameGpu, p: &AdaptiveParams, prepared: &Prepared, pending: Pending, out: &mut MethodOutput) -> Result<AdaptiveTrace> {
    let steer = prepared.steer.as_ref().expect("steered frame without its state");
    let words: Vec<u32> = readback::map_staging(fg.ctx, &steer.history)?;
    let mut trace = AdaptiveTrace::default();
    let mut quads = vec![ROOT];
    trace.rendered = candidates(0);
    for (level, &(read, evaluated, at)) in pending.reads.iter().enumerate() {
        let read = LevelRead { n: quads.len() as u64, ..read };
        let report = levels::parse_level(&prepared.b, &words[(at / 4) as usize..], level as u32, quads, evaluated, read);
        if let Some(e) = report.overflow_error(level as u32) {
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
    let w = (pending.weights_at / 4) as usize;
    trace.weights = bytemuck::cast_slice::<u32, f32>(&words[w..w + LATTICE_POINTS as usize]).to_vec();
    trace.samples = prepared.samples.clone();
    trace.triangles = vec![fg.scene_gpu.index_count as u64 / 3; trace.rendered.len()];
    out.shadow_maps = trace.rendered.len() as u32;
    out.syncs = 0;
    out.record = levels::record(p, &trace, 0, None, &fg.gbuffer);
    out.record["steer"] = serde_json::json!("gpu: no read-back in the frame; the level records are read after it");
    // What each level rasterized past level 0 (new_maps' `requested_only`).
    let one_chunk = (1..=p.max_level).all(|l| candidates(l).len() <= prepared.store.per_array as usize);
    out.record["steer_raster"] = serde_json::json!(if fg.raster.is_compute() && one_chunk {
        "compute: only the maps subdivide requested, dispatches sized on the GPU"
    } else {
        "every candidate layer cleared, drawn with the request flag as instance count"
    });
    out.pictures = if pending.pictures { pictures::all(fg, &trace, None) } else { Vec::new() };
    Ok(trace)
}
