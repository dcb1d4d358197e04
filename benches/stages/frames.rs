//! The adaptive stages and shade, timed inside whole frames (TimingMode::Stages waits after every
//! stage, so each stage's wall time is its own). Frames are rendered on demand and shared between
//! groups: every frame measures every stage once.

use criterion::{BenchmarkId, Criterion, SamplingMode, Throughput};
use penumbra::research::frame;
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::gpu::{GpuContext, Stage};
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;
use std::collections::{BTreeMap, HashMap};
use std::time::Duration;

pub struct FramePool<'a> {
    ctx: &'a GpuContext,
    scene: Scene,
    method: Method,
    /// Stage wall times (ms) of every frame rendered so far.
    frames: Vec<BTreeMap<String, f64>>,
    cursor: HashMap<String, usize>,
    /// From the first frame (the method is deterministic): maps, geometry pixels, Σ pixels evaluated.
    pub maps: u64,
    pub pixels: u64,
    pub pixel_quads: u64,
}

impl<'a> FramePool<'a> {
    pub fn new(ctx: &'a GpuContext, scene: Scene, method: &str) -> Self {
        let method = Method::parse(method, &[]).expect("method");
        let mut pool = FramePool {
            ctx,
            scene,
            method,
            frames: Vec::new(),
            cursor: HashMap::new(),
            maps: 0,
            pixels: 0,
            pixel_quads: 0,
        };
        let first =
            frame::render(ctx, &pool.scene, &pool.method, TimingMode::Stages).expect("frame");
        pool.maps = first.output.shadow_maps as u64;
        pool.pixels = first.gbuffer.geometry_count() as u64;
        pool.pixel_quads = first.output.record["levels"]
            .as_array()
            .map(|levels| {
                levels
                    .iter()
                    .filter_map(|l| l["pixels_evaluated"].as_u64())
                    .sum()
            })
            .unwrap_or(0);
        pool
    }

    /// Total wall time of `stages` over the next `iters` frames (rendering more when needed).
    fn take(&mut self, key: &str, stages: &[Stage], iters: u64) -> Duration {
        let start = *self.cursor.get(key).unwrap_or(&0);
        while self.frames.len() < start + iters as usize {
            let r = frame::render(self.ctx, &self.scene, &self.method, TimingMode::Stages)
                .expect("frame");
            self.frames.push(r.stages_ms);
        }
        self.cursor.insert(key.to_string(), start + iters as usize);
        let ms: f64 = self.frames[start..start + iters as usize]
            .iter()
            .map(|f| stages.iter().filter_map(|s| f.get(s.name)).sum::<f64>())
            .sum();
        Duration::from_secs_f64(ms / 1e3).max(Duration::from_nanos(1))
    }
}

fn frame_group<'c>(
    c: &'c mut Criterion,
    name: &str,
) -> criterion::BenchmarkGroup<'c, criterion::measurement::WallTime> {
    let mut group = c.benchmark_group(name);
    // Each iteration is a whole frame: few, equal-sized samples.
    group.sample_size(10).sampling_mode(SamplingMode::Flat);
    group
}

/// reproject_count, neighbourhood, quad_count + subdivide: one iteration = one adaptive frame's
/// worth of the stage (all levels); throughput in pixel·quad evaluations.
pub fn adaptive_stages(c: &mut Criterion, pool: &mut FramePool) {
    println!(
        "adaptive stages on `{}` ({}x{}, {} maps, {} pixel·quad evaluations per frame)",
        pool.scene.name,
        pool.scene.render.width,
        pool.scene.render.height,
        pool.maps,
        pool.pixel_quads
    );
    for (group_name, stages) in [
        ("reproject_count", &[Stage::REPROJECT_COUNT][..]),
        ("neighbourhood", &[Stage::NEIGHBOURHOOD][..]),
        (
            "quad_count+subdivide",
            &[Stage::QUAD_COUNT, Stage::SUBDIVIDE][..],
        ),
    ] {
        let mut group = frame_group(c, group_name);
        group.throughput(Throughput::Elements(pool.pixel_quads));
        group.bench_function(BenchmarkId::new("adaptive_frame", &pool.scene.name), |b| {
            b.iter_custom(|iters| pool.take(group_name, stages, iters))
        });
        group.finish();
    }
}

/// shade: one iteration = one frame's shading; throughput in pixel·map lookups (geometry pixels ×
/// maps). Regular reads its depth maps; adaptive (scope = global) reads the cached shadow-test bits.
pub fn shade<'a>(c: &mut Criterion, adaptive: &mut FramePool<'a>, regular: &mut FramePool<'a>) {
    let mut group = frame_group(c, "shade");
    for (id, pool) in [("regular_maps", regular), ("adaptive_masks", adaptive)] {
        group.throughput(Throughput::Elements(pool.pixels * pool.maps));
        group.bench_function(BenchmarkId::new(id, format!("{}_maps", pool.maps)), |b| {
            b.iter_custom(|iters| pool.take("shade", &[Stage::SHADE], iters))
        });
    }
    group.finish();
}

/// hybrid_build and the hard shadow's lookup on hybrid maps (docs/hybrid.md): one iteration = one
/// `hard` frame's merge of its 2048² map into 512² (throughput in full-resolution texels), and its
/// shade on the hybrid store against a plain 2048² map (throughput in pixel lookups).
pub fn hybrid(c: &mut Criterion, ctx: &GpuContext, scene: Scene) {
    let mut plain = scene.clone();
    plain.render.shadow_map_size = 2048;
    let mut hybrid = scene;
    hybrid.render.maps = penumbra::research::scene::MapKind::Hybrid;
    hybrid.render.hybrid = penumbra::research::scene::HybridDef {
        base: 2048,
        levels: 2,
        eps: 0.25,
    };
    hybrid.render.shadow_map_size = 2048;
    let mut plain = FramePool::new(ctx, plain, "hard");
    let mut hybrid = FramePool::new(ctx, hybrid, "hard");
    let mut group = frame_group(c, "hybrid_build");
    group.throughput(Throughput::Elements(2048 * 2048));
    group.bench_function(
        BenchmarkId::new("hard_2048_to_512", &hybrid.scene.name),
        |b| b.iter_custom(|iters| hybrid.take("hybrid_build", &[Stage::HYBRID_BUILD], iters)),
    );
    group.finish();
    let mut group = frame_group(c, "shade_hard");
    for (id, pool) in [
        ("plain_2048", &mut plain),
        ("hybrid_2048_to_512", &mut hybrid),
    ] {
        group.throughput(Throughput::Elements(pool.pixels));
        group.bench_function(BenchmarkId::new(id, &pool.scene.name), |b| {
            b.iter_custom(|iters| pool.take("shade", &[Stage::SHADE], iters))
        });
    }
    group.finish();
}
