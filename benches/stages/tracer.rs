//! The CPU reference tracer: shadow rays per second against the scene's BVH, from a real G-buffer
//! (the 512x512 stage scene), with the continuous mode's jittered light samples.

use criterion::{BenchmarkId, Criterion, SamplingMode, Throughput};
use penumbra::frame;
use penumbra::reference::truth::{ray_offset, surface_points};
use penumbra::gpu::GpuContext;
use penumbra::reference::{trace_visibility, RefLight, ReferenceMode, Tracer};
use penumbra::scene::Scene;

pub fn reference_tracer(c: &mut Criterion, ctx: &GpuContext, scene: Scene) {
    let g = frame::gbuffer_only(ctx, &scene).expect("G-buffer for the tracer bench");
    let points = surface_points(&g);
    let geometry = points.iter().filter(|p| p.is_some()).count() as u64;
    let tracer = Tracer::new(&scene.triangles());
    let light = RefLight { center: scene.light.center, edge_u: scene.light.edge_u, edge_v: scene.light.edge_v };
    let offset = ray_offset(&scene);
    let mut group = c.benchmark_group("reference_tracer");
    group.sample_size(10).sampling_mode(SamplingMode::Flat);
    // 4x4 samples per pixel keeps one iteration near a second on 2 cores; rays are counted exactly.
    let mode = ReferenceMode::Continuous { m: 4, seed: 1 };
    let before = tracer.rays_traced();
    trace_visibility(&tracer, &points, &light, &mode, offset, &|_| {});
    let rays = tracer.rays_traced() - before;
    group.throughput(Throughput::Elements(rays));
    group.bench_function(BenchmarkId::new("continuous_4x4", format!("{geometry}_pixels_{}_triangles", scene.triangle_count())), |b| {
        b.iter(|| trace_visibility(&tracer, &points, &light, &mode, offset, &|_| {}))
    });
    group.finish();
}
