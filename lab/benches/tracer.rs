//! The CPU reference tracer: shadow rays per second against the scene's BVH, from a real G-buffer
//! (the 512x512 stage scene), with the continuous mode's jittered light samples.
//! `cargo bench -p penumbra-lab --bench tracer -- --warm-up-time 1 --measurement-time 3`.

use criterion::{BenchmarkId, Criterion, SamplingMode, Throughput};
use penumbra::research::frame;
use penumbra::research::gpu::GpuContext;
use penumbra::research::scene::Scene;
use penumbra_lab::reference::truth::{ray_offset, surface_points};
use penumbra_lab::reference::{trace_visibility, RefLight, ReferenceMode, Tracer};

// The engine's bench scenes (benches/stages/scenes.rs).
#[allow(dead_code)]
#[path = "../../benches/stages/scenes.rs"]
mod scenes;

fn main() {
    // Headless: the Vulkan loader probes Wayland, which prints an error line when this is unset.
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
    std::env::set_var("PENUMBRA_NO_PROGRESS", "1");
    let ctx = GpuContext::new().unwrap_or_else(|e| panic!("benches need a GPU adapter: {e}"));
    let s = &ctx.summary;
    println!(
        "adapter: {} ({}, {}, {} {})",
        s.name, s.backend, s.device_type, s.driver, s.driver_info
    );
    let mut c = Criterion::default().configure_from_args();
    reference_tracer(&mut c, &ctx, scenes::stage_scene());
    c.final_summary();
}

pub fn reference_tracer(c: &mut Criterion, ctx: &GpuContext, scene: Scene) {
    let g = frame::gbuffer_only(ctx, &scene).expect("G-buffer for the tracer bench");
    let points = surface_points(&g);
    let geometry = points.iter().filter(|p| p.is_some()).count() as u64;
    let tracer = Tracer::new(&scene.triangles());
    let light = RefLight {
        center: scene.light.center,
        edge_u: scene.light.edge_u,
        edge_v: scene.light.edge_v,
    };
    let offset = ray_offset(&scene);
    let mut group = c.benchmark_group("reference_tracer");
    group.sample_size(10).sampling_mode(SamplingMode::Flat);
    // 4x4 samples per pixel keeps one iteration near a second on 2 cores; rays are counted exactly.
    let mode = ReferenceMode::Continuous { m: 4, seed: 1 };
    let before = tracer.rays_traced();
    trace_visibility(&tracer, &points, &light, &mode, offset, &|_| {});
    let rays = tracer.rays_traced() - before;
    group.throughput(Throughput::Elements(rays));
    group.bench_function(
        BenchmarkId::new(
            "continuous_4x4",
            format!("{geometry}_pixels_{}_triangles", scene.triangle_count()),
        ),
        |b| b.iter(|| trace_visibility(&tracer, &points, &light, &mode, offset, &|_| {})),
    );
    group.finish();
}
