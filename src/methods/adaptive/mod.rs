//! Adaptive light-source sampling (seed 000 / Schwärzler et al. 2012), GPU-driven per level:
//!   shadow_raster (new samples) ─► shadow_test ─► reproject_count ─► neighbourhood ─► quad_count
//!   ─► subdivide [─► compact under scope = local] ─► one small read-back ─► next level.
//! scope = global shades every pixel with every map (the seed); scope = local refines each pixel only
//! inside the quads whose penumbra it lies in (method.md §4.2).

pub mod buffers;
mod levels;
pub mod params;
mod steer;
mod pictures;
mod weights;

pub use levels::{LevelRecord, LevelReport};
pub use weights::sample_weights;

use super::hybrid_maps::{self, HybridMaps};
use params::SplitRule;
use super::{AdaptiveParams, Family, MethodInfo, MethodOutput, MethodState, Param, ShadowMethod, Scope};
use crate::methods::adaptive::buffers::{AdaptiveBuffers, CONTROL_BYTES, CULL_TILE_WORDS, LATTICE_POINTS, LATTICE_SIDE, QUAD_CAPACITY};
use crate::stages::{
    compact::Compact, cull::Cull, groups, probe::Probe, neighbourhood::Neighbourhood, quad_count::QuadCount, reproject_count::ReprojectCount,
    shadow_test::ShadowTest, subdivide::Subdivide, LINE_WORKGROUP,
};
use crate::stages::FrameGpu;
use crate::gpu::readback;
use crate::gpu::structs::{GpuControl, GpuLevel, GpuQuad, GpuSample};
use crate::scene::light::sample_view;
use crate::render::shadow_raster::{self, RasterJob, ShadowMapArray};
use crate::gpu::timing::StageTimer;
use crate::{Error, Result};

pub const INFO: MethodInfo = MethodInfo {
    name: "adaptive",
    family: Family::MultiSample,
    summary: "adaptive light-source sampling (seed 000): split light quads whose penumbra pixels exceed p_m",
    params: &[
        Param { key: "preset", default: "none", help: "seed (the seed's settings) or balanced (p_m 0, max_level 3, Coons weights; docs/bench.md)" },
        Param { key: "p_m", default: "0", help: "split when a quad's low-quality pixels exceed p_m (-1 always, inf never)" },
        Param { key: "p_share", default: "none", help: "split threshold as a share of the geometry pixels, 0..=1 (instead of p_m)" },
        Param { key: "growth", default: "1", help: "threshold factor per level for p_m or p_share, 1..=1e6" },
        Param { key: "tol", default: "none", help: "error budget: split when a quad's estimated RMSE exceeds tol (instead of p_m)" },
        Param { key: "max_level", default: "4", help: "deepest quadtree level, 0..=4 (4 = the 17×17 lattice)" },
        Param { key: "weights", default: "level", help: "sample weights: level (the seed's 1/(2^l+1)²), area or coons" },
        Param { key: "scope", default: "global", help: "global (every map shades every pixel) or local (region-local refinement)" },
        Param { key: "layout", default: "lattice", help: "lattice (the seed: corner to corner) or centred (inset half a finest cell: the midpoint rule when fully split; global scope)" },
        Param { key: "scissor", default: "off", help: "scope=local only: raster each map only over the texels its pixels test" },
        Param { key: "steer", default: "cpu", help: "cpu: one read-back per level; gpu: the levels drive each other on the GPU, no read-back (scope=global, lattice layout; slower on an H100 today, docs/bench.md)" },
        Param { key: "cull", default: "off", help: "scope=local only: raster each map only with the triangles that can change a texel its pixels test (docs/gpu-frame.md)" },
        Param { key: "items", default: "what one binding holds", help: "scope=local only: cap on the (pixel, quad) item list; past it the frame fails with an overflow, never clips" },
    ],
    parse: |p| Ok(std::sync::Arc::new(Adaptive(AdaptiveParams::from_map(p)?))),
};

/// The adaptive method with its parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Adaptive(pub AdaptiveParams);

impl ShadowMethod for Adaptive {
    fn name(&self) -> &'static str {
        "adaptive"
    }
    fn label(&self) -> String {
        self.0.label()
    }
    fn params_json(&self) -> serde_json::Value {
        serde_json::to_value(&self.0).unwrap_or_default()
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        Ok(Box::new(State { p: self.0.clone(), prepared: prepare(fg, &self.0)?, pending: None }))
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// Built once per scene and settings; `reset` zero-fills the buffers and restores the samples.
struct State {
    p: AdaptiveParams,
    prepared: Prepared,
    /// A GPU-steered frame's record, read in `finish`.
    pending: Option<steer::Pending>,
}

impl MethodState for State {
    fn reset(&mut self, fg: &FrameGpu) -> Result<()> {
        let pr = &mut self.prepared;
        pr.samples = lattice_samples(fg, &self.p);
        fg.ctx.queue.write_buffer(&pr.b.samples, 0, bytemuck::cast_slice(&pr.samples));
        pr.store.used = 0;
        if let Some(h) = pr.store.hybrid.as_mut() {
            h.reset(fg);
        }
        pr.b.reset_frame(fg.ctx)
    }
    fn run(&mut self, fg: &FrameGpu, timer: &mut StageTimer, capture: bool) -> Result<MethodOutput> {
        if !capture && self.prepared.steer.is_some() {
            let (out, pending) = steer::run(fg, timer, &self.p, &mut self.prepared)?;
            self.pending = Some(pending);
            return Ok(out);
        }
        let (mut out, trace) = run(fg, timer, &self.p, &mut self.prepared, capture)?;
        out.detail = Some(Box::new(trace));
        Ok(out)
    }
    fn finish(&mut self, fg: &FrameGpu, out: &mut MethodOutput) -> Result<()> {
        match self.pending.take() {
            Some(pending) => steer::finish(fg, &self.p, &self.prepared, pending, out),
            None => Ok(()),
        }
    }
}

/// The trace of an adaptive run (every run keeps one; `capture` adds the intermediate buffers).
pub fn trace_of(out: &MethodOutput) -> Option<&AdaptiveTrace> {
    out.detail.as_ref()?.downcast_ref()
}

/// Lattice index of (i, j).
pub fn lattice_index(i: u32, j: u32) -> u32 {
    j * LATTICE_SIDE + i
}

/// Views of all 289 lattice samples (layer and array are filled in when a map is rendered).
pub fn lattice_samples(fg: &FrameGpu, p: &AdaptiveParams) -> Vec<GpuSample> {
    let s = fg.scene;
    (0..LATTICE_POINTS)
        .map(|k| {
            let (i, j) = (k % LATTICE_SIDE, k / LATTICE_SIDE);
            let y = s.light.point(p.light_coord(i), p.light_coord(j));
            sample_view(&s.light, y, &s.bounds, s.render.shadow_map_size, k)
        })
        .collect()
}

/// Everything a test may want to see of one run besides the visibility image.
#[derive(Clone, Debug, Default)]
pub struct AdaptiveTrace {
    pub levels: Vec<LevelReport>,
    /// Lattice indices in the order their maps were rendered.
    pub rendered: Vec<u32>,
    pub weights: Vec<f32>,
    /// Captured for twin tests: each rendered map (lattice index, row-major depths).
    pub maps: Vec<(u32, Vec<f32>)>,
    /// The sample records as the kernels saw them (layer and array filled in).
    pub samples: Vec<GpuSample>,
    /// Triangles rasterized per map, in `rendered` order (the whole mesh unless culled).
    pub triangles: Vec<u64>,
    /// Lattice indices whose maps were drawn from a culled index list.
    pub culled: Vec<u32>,
}

/// Shadow maps for the adaptive method: `global` reuses one array chunk by chunk (maps are needed
/// only until shadow_test has cached them); `local` keeps every map alive in up to two arrays.
struct MapStore {
    arrays: Vec<ShadowMapArray>,
    per_array: u32,
    used: u32,
    /// `maps = hybrid` (scope = global): a few raster layers merged into a store, tested, dropped.
    hybrid: Option<HybridMaps>,
}

/// Buffers, shadow-map arrays and pipelines, allocated (and zero-filled) before the frame's clock
/// starts, as a renderer would keep them from frame to frame.
pub struct Prepared {
    b: AdaptiveBuffers,
    store: MapStore,
    passes: Passes,
    samples: Vec<GpuSample>,
    /// scope = local with culling: the index slots, and the indices kept per lattice sample
    /// (copied from the draw arguments, read back with each level).
    cull: Option<(Cull, wgpu::Buffer)>,
    /// The GPU-steered loop's state, where this setting allows it (steer::eligible).
    steer: Option<steer::Steer>,
}

pub fn prepare(fg: &FrameGpu, p: &AdaptiveParams) -> Result<Prepared> {
    let ctx = fg.ctx;
    let scene = fg.scene;
    let local = p.scope == Scope::Local;
    let (w, h) = (fg.gbuffer.width, fg.gbuffer.height);
    let samples = lattice_samples(fg, p);
    let b = AdaptiveBuffers::new(ctx, w, h, &samples, local, p.items)?;
    b.zero_fill(ctx)?;
    let hybrid = scene.render.maps == crate::scene::MapKind::Hybrid;
    if hybrid && local {
        return Err(Error::Param(
            "adaptive: maps = hybrid needs scope = global (scope = local keeps every map alive for probe and reproject_count, which read depth arrays)".into(),
        ));
    }
    let per_array = shadow_raster::maps_per_array(ctx, scene.render.shadow_map_size, scene.render.shadow_map_budget_mib)?;
    let store = if hybrid {
        // Maps live only until shadow_test has cached them: one raster batch per store.
        let maps = HybridMaps::new(fg, LATTICE_POINTS, hybrid_maps::TRANSIENT_LAYERS)?;
        MapStore { arrays: Vec::new(), per_array: maps.layers(), used: 0, hybrid: Some(maps) }
    } else if local {
        // Every map stays alive: the lattice needs up to 289, split across two arrays at the layer limit.
        let need = LATTICE_POINTS;
        let budget_maps = per_array as u64 * if per_array >= need { 1 } else { 2 };
        if (budget_maps as u32) < need && per_array < ctx.limits().max_texture_array_layers {
            return Err(Error::Limit(format!(
                "adaptive scope=local keeps every map alive: up to 289 maps of {0}x{0} do not fit shadow_map_budget_mib = {1}; raise the budget or use scope=global",
                scene.render.shadow_map_size, scene.render.shadow_map_budget_mib
            )));
        }
        let first = per_array.min(need);
        let mut arrays = vec![shadow_raster::allocate(ctx, scene.render.shadow_map_size, first)];
        if first < need {
            arrays.push(shadow_raster::allocate(ctx, scene.render.shadow_map_size, need - first));
        }
        MapStore { arrays, per_array: first, used: 0, hybrid: None }
    } else {
        let chunk = per_array.min(LATTICE_POINTS);
        MapStore { arrays: vec![shadow_raster::allocate(ctx, scene.render.shadow_map_size, chunk)], per_array: chunk, used: 0, hybrid: None }
    };
    let passes = Passes {
        shadow_test: ShadowTest::new(fg.ctx, fg.scene.render.maps, local)?,
        reproject_count: ReprojectCount::new(fg)?,
        neighbourhood: Neighbourhood::new(fg)?,
        quad_count: QuadCount::new(fg)?,
        subdivide: Subdivide::new(fg)?,
        compact: Compact::new(fg)?,
        probe: Probe::new(fg)?,
    };
    for array in &store.arrays {
        shadow_raster::clear_all(ctx, array)?;
    }
    let cull = if p.culls() {
        Cull::new(fg, LATTICE_POINTS)?.map(|c| (c, readback::zeroed_storage(ctx, "culled indices per sample", LATTICE_POINTS as u64 * 4)))
    } else {
        None
    };
    // maps = hybrid merges each batch into a store whose allocation the CPU reads: it waits.
    let steer = if !hybrid && steer::eligible(p, &b) { Some(steer::Steer::new(fg, p, &b)?) } else { None };
    Ok(Prepared { b, store, passes, samples, cull, steer })
}

/// `capture` reads back every intermediate buffer (maps, masks, comparison maps) for twin tests;
/// it adds synchronisations, so it is for tests only.
pub fn run(fg: &FrameGpu, timer: &mut StageTimer, p: &AdaptiveParams, prepared: &mut Prepared, capture: bool) -> Result<(MethodOutput, AdaptiveTrace)> {
    let ctx = fg.ctx;
    let local = p.scope == Scope::Local;
    let (w, h) = (fg.gbuffer.width, fg.gbuffer.height);
    let (b, store, passes, samples) = (&prepared.b, &mut prepared.store, &prepared.passes, &mut prepared.samples);
    let cull = prepared.cull.as_ref();
    // compact grows each sample's texel rectangle for the scissor and for culling.
    let grow_rects = p.scissor || cull.is_some();
    let dense_groups_x = groups(h * b.flag_words_per_row, LINE_WORKGROUP[0]);
    let level_uniform = |level: u32, quad_count: u32, first_quad: u32| gpu_level(p, b, dense_groups_x, level, quad_count, first_quad);
    // The counters (geometry pixels, appends) start from zero every frame.
    ctx.queue.write_buffer(&b.control, 0, &[0u8; CONTROL_BYTES as usize]);

    // Level 0: the whole light, its four corners requested.
    let root = GpuQuad { i: 0, j: 0, size: 16, parent: u32::MAX };
    ctx.queue.write_buffer(&b.quads[0], 0, bytemuck::bytes_of(&root));
    let corners = [lattice_index(0, 0), lattice_index(16, 0), lattice_index(0, 16), lattice_index(16, 16)];
    let mut state = vec![0u32; LATTICE_POINTS as usize];
    for k in corners {
        state[k as usize] = 1;
    }
    ctx.queue.write_buffer(&b.lattice_state, 0, bytemuck::cast_slice(&state));
    if local {
        let level = readback::uniform_buffer(ctx, "level", &level_uniform(0, 1, 0));
        timer.stage(ctx, "compact", |enc| {
            passes.compact.record_seed(fg, enc, b, &level, &b.items[0]);
            Ok(())
        })?;
    }

    if cull.is_some() {
        // Every pixel tests the corners: each of their tiles takes an infinite limit, so their cull
        // drops only what can change no texel (triangles that cover no texel centre, back faces).
        let every = vec![f32::INFINITY.to_bits(); CULL_TILE_WORDS as usize];
        for k in corners {
            ctx.queue.write_buffer(&b.tiles, k as u64 * CULL_TILE_WORDS as u64 * 4, bytemuck::cast_slice(&every));
        }
    }

    let mut trace = AdaptiveTrace::default();
    let mut new: Vec<u32> = corners.to_vec();
    let mut quad_count = 1u32;
    let mut syncs = 0u32;
    let mut rects: Option<Vec<[u32; 4]>> = None;
    let bar = crate::progress::bar(p.max_level as u64 + 1, "adaptive levels");
    for level in 0..=p.max_level {
        let cur = (level % 2) as usize;
        let nxt = 1 - cur;
        // New maps: raster (with scissor under scope = local) and, under scope = global, cache their tests.
        // Level 0's corners precede every rectangle: no scissor.
        render_new(fg, timer, b, store, samples, &new, rects.as_deref(), cull, local, passes, &mut trace, capture)?;

        // Under scope = global the counts only feed the split rule: a rule that cannot depend on them
        // (always, never) and the last level (nothing splits) skip the count stages.
        let counted = matches!(p.split_rule(level), SplitRule::Threshold(_) | SplitRule::Share(_));
        let evaluate = local || (level < p.max_level && counted);
        // Under scope = local the last level splits nothing either: its items add their counts to V
        // at once (reproject_count `last`), with no comparison map, neighbourhood or compact.
        let last_local = local && level == p.max_level;
        ctx.queue.write_buffer(&b.control, 0, &[0u8; 8]);
        if local {
            ctx.queue.write_buffer(&b.control, std::mem::offset_of!(GpuControl, lookups) as u64, &[0u8; 4]);
        }
        if local && level > 0 {
            // Uniform pixels of last level's split quads test the new samples (the blind-spot fix).
            let lv = readback::uniform_buffer(ctx, "level", &level_uniform(level, quad_count, 0));
            let maps = store.views();
            timer.stage(ctx, "probe", |enc| {
                passes.probe.record_begin(fg, enc, b, &lv);
                Ok(())
            })?;
            timer.stage(ctx, "shadow_test", |enc| {
                passes.shadow_test.record_probes(fg, enc, b, &b.quads[cur], maps);
                Ok(())
            })?;
            timer.stage(ctx, "probe", |enc| {
                passes.probe.record(fg, enc, b, &lv, &b.quads[cur], &b.items[cur]);
                Ok(())
            })?;
        }
        ctx.queue.write_buffer(&b.quad_counters, 0, &vec![0u8; QUAD_CAPACITY as usize * 4]);
        if local {
            let lv = readback::uniform_buffer(ctx, "level", &level_uniform(level, quad_count, 0));
            let items = &b.items[cur];
            let maps = store.views();
            timer.stage(ctx, "reproject_count", |enc| {
                // The items compact (and probe) appended become this level's work.
                passes.reproject_count.record_begin(fg, enc, b, &lv);
                // Only this level's quads: the buffers are sized for 256. The last level writes none.
                if !last_local {
                    enc.clear_buffer(&b.counts, 0, Some(b.counts_bytes_per_quad() * quad_count as u64));
                }
                Ok(())
            })?;
            timer.stage(ctx, "shadow_test", |enc| {
                passes.shadow_test.record_list(fg, enc, b, &b.quads[cur], items, maps);
                Ok(())
            })?;
            timer.stage(ctx, "reproject_count", |enc| {
                if last_local {
                    passes.reproject_count.record_last(fg, enc, b, &lv, &b.quads[cur], items);
                } else {
                    passes.reproject_count.record_list(fg, enc, b, &lv, &b.quads[cur], items);
                }
                Ok(())
            })?;
            // neighbourhood's list also counts each quad's low-quality pixels: no quad_count pass.
            if !last_local {
                timer.stage(ctx, "neighbourhood", |enc| {
                    enc.clear_buffer(&b.flags, 0, Some(b.flags_bytes_per_quad() * quad_count as u64));
                    passes.neighbourhood.record_list(fg, enc, b, &lv, items);
                    Ok(())
                })?;
            }
        } else if evaluate {
            // Dense: every pixel x every active quad, in batches that fit one comparison-map buffer.
            let single = quad_count <= b.count_quads;
            for first in (0..quad_count).step_by(b.count_quads as usize) {
                let n = b.count_quads.min(quad_count - first);
                let lv = readback::uniform_buffer(ctx, "level", &level_uniform(level, n, first));
                timer.stage(ctx, "reproject_count", |enc| {
                    passes.reproject_count.record_dense(fg, enc, b, &lv, &b.quads[cur]);
                    Ok(())
                })?;
                // GPU-driven: the previous subdivide wrote these dispatches' sizes (flag words x quads).
                let indirect = single && level > 0;
                timer.stage(ctx, "neighbourhood", |enc| {
                    passes.neighbourhood.record_dense(fg, enc, b, &lv);
                    Ok(())
                })?;
                timer.stage(ctx, "quad_count", |enc| {
                    passes.quad_count.record(fg, enc, b, &lv, n, indirect);
                    Ok(())
                })?;
            }
        }
        let lv = readback::uniform_buffer(ctx, "level", &level_uniform(level, quad_count, 0));
        timer.stage(ctx, "subdivide", |enc| {
            passes.subdivide.record(fg, enc, b, &lv, &b.quads[cur], &b.quads[nxt]);
            Ok(())
        })?;
        if local && !last_local {
            if grow_rects {
                let init: Vec<[u32; 4]> = vec![[u32::MAX, u32::MAX, 0, 0]; LATTICE_POINTS as usize];
                ctx.queue.write_buffer(&b.rects, 0, bytemuck::cast_slice(&init));
            }
            timer.stage(ctx, "compact", |enc| {
                // compact grows the tiles of the next level's new samples only, all of them among
                // its candidates: clear those (a twentieth to three quarters of the 289 samples'
                // tiles). The last level splits nothing and grows no tile.
                if cull.is_some() && level < p.max_level {
                    let bytes = CULL_TILE_WORDS as u64 * 4;
                    for k in steer::candidates(level + 1) {
                        enc.clear_buffer(&b.tiles, k as u64 * bytes, Some(bytes));
                    }
                }
                passes.compact.record_main(fg, enc, b, &lv, &b.items[cur], &b.items[nxt], &b.quads[nxt], grow_rects);
                Ok(())
            })?;
        }
        // The one read-back of this level.
        timer.flush(ctx);
        // The local last level has no comparison maps or low-quality flags to report.
        let flagged = evaluate && !last_local;
        let pictures = fg.pictures && flagged && (local || quad_count <= b.count_quads);
        let evaluated = trace.levels.last().map_or_else(|| vec![root], |r: &LevelReport| r.next_quads.clone());
        let report = timer.cpu("readback_level", || levels::read_level(fg, b, level, evaluated, &b.quads[nxt], cull.map(|c| &c.1), pictures, flagged, local, capture))?;
        syncs += 1;
        if report.overflow != 0 {
            return Err(Error::Overflow(format!(
                "adaptive level {level}: {} (flags {:#x}); the run is not valid",
                if report.overflow & 2 != 0 {
                    "the (pixel, quad) item list exceeded its capacity"
                } else if report.overflow & 4 != 0 {
                    "the probe list exceeded its capacity"
                } else {
                    "the quad list exceeded 256"
                },
                report.overflow
            )));
        }
        rects = if local && p.scissor { Some(report.rects.clone()) } else { None };
        new = report.new_samples.clone();
        quad_count = report.next_quad_count;
        trace.levels.push(report);
        bar.inc(1);
        if quad_count == 0 {
            break;
        }
    }
    bar.finish_and_clear();

    let last = trace.levels.last().cloned().unwrap_or_default();
    let whole = fg.scene_gpu.index_count as u64 / 3;
    trace.triangles = trace.rendered.iter().map(|&k| if trace.culled.contains(&k) { last.triangles[k as usize] as u64 / 3 } else { whole }).collect();
    let weights = sample_weights(p, &trace.levels, &last.sample_level, &trace.rendered);
    trace.weights = weights.clone();
    trace.samples = samples.clone();
    if local {
        let lv = readback::uniform_buffer(ctx, "level", &level_uniform(p.max_level, 0, 0));
        timer.stage(ctx, "shade", |enc| {
            passes.compact.record_resolve(fg, enc, b, &lv);
            Ok(())
        })?;
    } else {
        ctx.queue.write_buffer(&b.weights, 0, bytemuck::cast_slice(&weights));
        timer.stage(ctx, "shade", |enc| {
            fg.shade.record_masks(ctx, enc, &fg.frame_buffer, &b.weights, &fg.gbuffer, &b.masks, &fg.visibility);
            Ok(())
        })?;
    }
    let consulted: Option<Vec<u32>> = if local && fg.pictures {
        timer.flush(ctx);
        Some(timer.cpu("pictures", || readback::read_buffer(ctx, &b.consulted, w as u64 * h as u64 * 40))?)
    } else {
        None
    };
    let pictures = if fg.pictures { pictures::all(fg, &trace, consulted.as_deref()) } else { Vec::new() };
    // The hybrid store's allocation read-backs are syncs the representation needs.
    syncs += store.hybrid.as_ref().map_or(0, |h| h.stats.syncs);
    let mut record = levels::record(p, &trace, syncs, consulted.as_deref(), &fg.gbuffer);
    if let Some(h) = &store.hybrid {
        record["hybrid"] = h.record();
    }
    Ok((MethodOutput { shadow_maps: trace.rendered.len() as u32, syncs, record, pictures, detail: None }, trace))
}

/// The uniform of one level (a batch of `quad_count` quads from `first_quad` in dense mode).
fn gpu_level(p: &AdaptiveParams, b: &AdaptiveBuffers, dense_groups_x: u32, level: u32, quad_count: u32, first_quad: u32) -> GpuLevel {
    let (split_mode, p_m, split_share) = match p.split_rule(level) {
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
        p_m,
        split_mode,
        split_share,
        words_per_row: b.words_per_row,
        flag_words_per_row: b.flag_words_per_row,
        item_capacity: b.item_capacity,
        work_count: 0,
        dense_groups_x,
        quad_capacity: QUAD_CAPACITY,
        pad0: 0,
        ..Default::default()
    }
}

/// subdivide's split modes (GpuLevel.split_mode).
const SPLIT_THRESHOLD: u32 = 0;
const SPLIT_ALWAYS: u32 = 1;
const SPLIT_NEVER: u32 = 2;
const SPLIT_SHARE: u32 = 3;

struct Passes {
    shadow_test: ShadowTest,
    reproject_count: ReprojectCount,
    neighbourhood: Neighbourhood,
    quad_count: QuadCount,
    subdivide: Subdivide,
    compact: Compact,
    probe: Probe,
}

impl MapStore {
    fn views(&self) -> [&wgpu::TextureView; 2] {
        let a = &self.arrays[0].array_view;
        [a, self.arrays.get(1).map(|x| &x.array_view).unwrap_or(a)]
    }
}

/// Rasterizes the maps of `new` (sorted, so layer assignment is deterministic) and, under
/// scope = global, caches their shadow tests; chunks when more maps than one array holds.
#[allow(clippy::too_many_arguments)]
fn render_new(
    fg: &FrameGpu,
    timer: &mut StageTimer,
    b: &AdaptiveBuffers,
    store: &mut MapStore,
    samples: &mut [GpuSample],
    new: &[u32],
    rects: Option<&[[u32; 4]]>,
    cull: Option<&(Cull, wgpu::Buffer)>,
    local: bool,
    passes: &Passes,
    trace: &mut AdaptiveTrace,
    capture: bool,
) -> Result<()> {
    let ctx = fg.ctx;
    let mut ks = new.to_vec();
    ks.sort_unstable();
    if let Some(h) = store.hybrid.as_mut() {
        return render_new_hybrid(fg, timer, b, h, samples, &ks, passes, trace, capture);
    }
    let map_size = fg.scene.render.shadow_map_size;
    for chunk in ks.chunks(store.per_array as usize) {
        let mut jobs: Vec<(usize, RasterJob)> = Vec::new();
        for (n, &k) in chunk.iter().enumerate() {
            let slot = if local { store.used + n as u32 } else { n as u32 };
            let (array, layer) = (slot / store.per_array, slot % store.per_array);
            samples[k as usize].layer = layer;
            samples[k as usize].array = array;
            let scissor = rects.and_then(|r| scissor_rect(r[k as usize], map_size));
            // A map none of whose pixels is tested needs no raster at all: an empty rect.
            let skip = rects.is_some() && scissor.is_none();
            if !skip {
                jobs.push((array as usize, RasterJob { sample: k, layer, scissor }));
            }
            ctx.queue.write_buffer(&b.samples, k as u64 * std::mem::size_of::<GpuSample>() as u64, bytemuck::bytes_of(&samples[k as usize]));
        }
        if local {
            store.used += chunk.len() as u32;
        }
        for (a, array) in store.arrays.iter().enumerate() {
            let mine: Vec<RasterJob> = jobs.iter().filter(|(x, _)| *x == a).map(|(_, j)| *j).collect();
            if mine.is_empty() {
                continue;
            }
            let Some((cull, kept)) = cull else {
                timer.stage(ctx, "shadow_raster", |enc| {
                    fg.raster.record(ctx, enc, &fg.scene_gpu, &b.samples, array, &mine);
                    Ok(())
                })?;
                continue;
            };
            // Batches of slots: cull, then draw what each slot kept (the GPU writes the counts).
            for batch in mine.chunks(cull.slots as usize) {
                let ks: Vec<u32> = batch.iter().map(|j| j.sample).collect();
                timer.stage(ctx, "cull", |enc| {
                    cull.record(fg, enc, &b.samples, &b.tiles, &ks);
                    Ok(())
                })?;
                timer.stage(ctx, "shadow_raster", |enc| {
                    let drawn: Vec<(RasterJob, u64)> = batch.iter().enumerate().map(|(n, j)| (*j, Cull::args_offset(n as u32))).collect();
                    fg.raster.record_culled(ctx, enc, &fg.scene_gpu, &b.samples, array, &drawn, &cull.culled, &cull.args);
                    for (n, &k) in ks.iter().enumerate() {
                        enc.copy_buffer_to_buffer(&cull.args, Cull::args_offset(n as u32), kept, k as u64 * 4, 4);
                    }
                    Ok(())
                })?;
                trace.culled.extend_from_slice(&ks);
            }
        }
        if !local {
            timer.stage(ctx, "shadow_test", |enc| {
                passes.shadow_test.record(fg, enc, b, &store.arrays[0].array_view, chunk);
                Ok(())
            })?;
        }
        // Sample records of the next chunk overwrite this one's layers: submit before writing them.
        timer.flush(ctx);
        if capture {
            for &k in chunk {
                let s = &samples[k as usize];
                let map = crate::gpu::readback::read_texture(ctx, &store.arrays[s.array as usize].texture, s.layer, 4)?;
                trace.maps.push((k, map));
            }
        }
        trace.rendered.extend_from_slice(chunk);
    }
    Ok(())
}

/// `render_new` with `maps = hybrid` (scope = global): each batch of the transient raster is merged
/// into the store, tested by shadow_test (slot = lattice index) and dropped.
#[allow(clippy::too_many_arguments)]
fn render_new_hybrid(
    fg: &FrameGpu,
    timer: &mut StageTimer,
    b: &AdaptiveBuffers,
    maps: &mut HybridMaps,
    samples: &mut [GpuSample],
    ks: &[u32],
    passes: &Passes,
    trace: &mut AdaptiveTrace,
    capture: bool,
) -> Result<()> {
    let ctx = fg.ctx;
    let mut test = |fg: &FrameGpu, timer: &mut StageTimer, view: &wgpu::TextureView, slots: &[u32]| {
        timer.stage(ctx, "shadow_test", |enc| {
            passes.shadow_test.record(fg, enc, b, view, slots);
            Ok(())
        })
    };
    for chunk in ks.chunks(maps.layers() as usize) {
        for &k in chunk {
            samples[k as usize].layer = k;
            samples[k as usize].array = 0;
            ctx.queue.write_buffer(&b.samples, k as u64 * std::mem::size_of::<GpuSample>() as u64, bytemuck::bytes_of(&samples[k as usize]));
        }
        maps.render(fg, timer, &b.samples, chunk, &mut test)?;
        maps.flush(fg, timer, &mut test)?;
        if capture {
            // Tests only: the maps as the lookup reads them (the pool keeps them until the next build).
            timer.flush(ctx);
            let pool = maps.store.read_words(ctx, maps.store.capacity_words)?;
            let h = maps.store.settings;
            for &k in chunk {
                trace.maps.push((k, crate::stages::twin::hybrid_build::decode(&pool, k, h.base, h.levels)));
            }
        }
        trace.rendered.extend_from_slice(chunk);
    }
    Ok(())
}

/// Texel rectangle [min, max] → scissor (x, y, w, h), one texel of margin; None when empty.
fn scissor_rect(r: [u32; 4], size: u32) -> Option<[u32; 4]> {
    if r[0] > r[2] || r[1] > r[3] {
        return None;
    }
    let x0 = r[0].saturating_sub(1);
    let y0 = r[1].saturating_sub(1);
    let x1 = (r[2] + 2).min(size);
    let y1 = (r[3] + 2).min(size);
    Some([x0, y0, x1 - x0, y1 - y0])
}
