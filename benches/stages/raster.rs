//! shadow_raster (per map) and gbuffer, driven directly: record N passes, submit, wait.

use crate::scenes;
use criterion::{BenchmarkId, Criterion, Throughput};
use penumbra::research::frame::camera_uniform;
use penumbra::research::gpu::structs::GpuSample;
use penumbra::research::gpu::{readback, GpuContext};
use penumbra::research::render::gbuffer::GBufferPass;
use penumbra::research::render::shadow_raster::{self, RasterJob, ShadowRasterPass};
use penumbra::research::render::SceneGpu;
use penumbra::research::scene::light::sample_view;
use std::time::{Duration, Instant};

/// Maps recorded per submit: one array of this many layers is reused.
const LAYERS: u64 = 64;

fn label(triangles: usize) -> String {
    if triangles >= 1_000_000 {
        format!("{:.1}M_triangles", triangles as f64 / 1e6)
    } else {
        format!("{}k_triangles", triangles / 1000)
    }
}

/// One iteration = one 512² shadow map of the whole scene; throughput in triangles.
pub fn shadow_raster(c: &mut Criterion, ctx: &GpuContext) {
    let mut group = c.benchmark_group("shadow_raster");
    group.sample_size(10);
    for scene in scenes::raster_scenes() {
        let map_size = scene.render.shadow_map_size;
        let gpu_scene = SceneGpu::upload(ctx, &scene);
        let pass = ShadowRasterPass::new(ctx, scene.render.cull).expect("shadow_raster pipeline");
        // The 289 lattice points, so successive maps see the scene from different light samples.
        let samples: Vec<GpuSample> = (0..289u32)
            .map(|k| {
                let y = scene
                    .light
                    .point((k % 17) as f32 / 16.0, (k / 17) as f32 / 16.0);
                sample_view(&scene.light, y, &scene.bounds, map_size, k)
            })
            .collect();
        let buffer =
            readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty());
        let array = shadow_raster::allocate(ctx, map_size, LAYERS as u32);
        group.throughput(Throughput::Elements(scene.triangle_count() as u64));
        let id = BenchmarkId::new(format!("per_map_{map_size}"), label(scene.triangle_count()));
        group.bench_function(id, |b| {
            b.iter_custom(|iters| {
                let start = Instant::now();
                let mut done = 0;
                while done < iters {
                    let n = LAYERS.min(iters - done);
                    let jobs: Vec<RasterJob> = (0..n)
                        .map(|i| RasterJob {
                            sample: ((done + i) % 289) as u32,
                            layer: i as u32,
                            scissor: None,
                        })
                        .collect();
                    let mut encoder = ctx.device.create_command_encoder(&Default::default());
                    pass.record(ctx, &mut encoder, &gpu_scene, &buffer, &array, &jobs);
                    ctx.queue.submit([encoder.finish()]);
                    ctx.wait().expect("wait");
                    done += n;
                }
                start.elapsed()
            })
        });
    }
    group.finish();
}

/// One iteration = one 512x512 G-buffer of the scene; throughput in pixels.
pub fn gbuffer(c: &mut Criterion, ctx: &GpuContext) {
    let mut group = c.benchmark_group("gbuffer");
    group.sample_size(10);
    let pass = GBufferPass::new(ctx).expect("gbuffer pipeline");
    for scene in scenes::raster_scenes() {
        let (w, h) = (scene.render.width, scene.render.height);
        let gpu_scene = SceneGpu::upload(ctx, &scene);
        let target = GBufferPass::allocate(ctx, w, h).expect("gbuffer");
        let camera = camera_uniform(&scene);
        group.throughput(Throughput::Elements(w as u64 * h as u64));
        group.bench_function(
            BenchmarkId::new(format!("{w}x{h}"), label(scene.triangle_count())),
            |b| {
                b.iter_custom(|iters| {
                    let start = Instant::now();
                    let mut done = 0;
                    while done < iters {
                        let n = 8.min(iters - done);
                        let mut encoder = ctx.device.create_command_encoder(&Default::default());
                        for _ in 0..n {
                            pass.record(ctx, &mut encoder, &gpu_scene, &camera, &target);
                        }
                        ctx.queue.submit([encoder.finish()]);
                        ctx.wait().expect("wait");
                        done += n;
                    }
                    start.elapsed().max(Duration::from_nanos(1))
                })
            },
        );
    }
    group.finish();
}
