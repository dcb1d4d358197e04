//! raster_compute against the fixed-function shadow_raster: the same 25 light samples (regular:n=5's
//! lattice), the same maps, one chain of 25 maps against 25 render passes; each iteration records
//! all 25, submits and waits. On `bunny` (close-up: larger triangles) and `bunny-seed-framing` (the
//! whole mesh small in the map), both 512² maps and 1.2M triangles, when the mesh is in the cache
//! (`penumbra assets fetch`), else on `default` (said in the benchmark's name).

use criterion::{BenchmarkId, Criterion, Throughput};
use penumbra::research::gpu::structs::{GpuRasterJob, GpuSample};
use penumbra::research::gpu::{readback, GpuContext};
use penumbra::research::methods::fixed_samples::{regular_points, Layout};
use penumbra::research::render::shadow_raster::{self, RasterJob, ShadowRasterPass};
use penumbra::research::render::SceneGpu;
use penumbra::research::scene::light::sample_view;
use penumbra::research::scene::Scene;
use penumbra::research::stages::raster_compute::RasterCompute;
use std::time::Instant;

pub fn raster_compute(c: &mut Criterion, ctx: &GpuContext) {
    let mut group = c.benchmark_group("raster_compute");
    group.sample_size(10);
    for wanted in ["bunny", "bunny-seed-framing", "dragon"] {
        let scene = match Scene::load(wanted, &[]) {
            Ok(s) => s,
            Err(e) => {
                println!("raster_compute: {wanted} unavailable ({e}); measuring default");
                Scene::load("default", &[]).expect("built-in scene")
            }
        };
        let map_size = scene.render.shadow_map_size;
        let samples: Vec<GpuSample> = regular_points(5, Layout::Lattice)
            .iter()
            .enumerate()
            .map(|(k, &(u, v))| {
                sample_view(
                    &scene.light,
                    scene.light.point(u, v),
                    &scene.bounds,
                    map_size,
                    k as u32,
                )
            })
            .collect();
        let maps = samples.len() as u32;
        let gpu = SceneGpu::upload(ctx, &scene);
        let buffer =
            readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty());
        let fixed = ShadowRasterPass::new(ctx, scene.render.cull).expect("shadow_raster pipeline");
        let array = shadow_raster::allocate(ctx, map_size, maps);
        let compute = RasterCompute::new(
            ctx,
            map_size,
            scene.render.cull,
            maps,
            scene.render.shadow_map_budget_mib,
        )
        .expect("raster_compute");
        assert_eq!(compute.capacity, maps, "one chain of {maps} maps");
        let jobs: Vec<RasterJob> = (0..maps)
            .map(|k| RasterJob {
                sample: k,
                layer: k,
                scissor: None,
            })
            .collect();
        let chain: Vec<GpuRasterJob> = (0..maps)
            .map(|k| GpuRasterJob::whole(k, map_size))
            .collect();

        group.throughput(Throughput::Elements(
            scene.triangle_count() as u64 * maps as u64,
        ));
        let name =
            |stage: &str| BenchmarkId::new(format!("{stage}_{maps}_maps_{map_size}"), &scene.name);
        let time = |b: &mut criterion::Bencher, record: &dyn Fn(&mut wgpu::CommandEncoder)| {
            b.iter_custom(|iters| {
                let start = Instant::now();
                for _ in 0..iters {
                    let mut enc = ctx.device.create_command_encoder(&Default::default());
                    record(&mut enc);
                    ctx.queue.submit([enc.finish()]);
                    ctx.wait().expect("wait");
                }
                start.elapsed()
            })
        };
        group.bench_function(name("shadow_raster"), |b| {
            time(b, &|enc| {
                fixed.record(ctx, enc, &gpu, &buffer, &array, &jobs)
            })
        });
        group.bench_function(name("raster_compute"), |b| {
            time(b, &|enc| compute.record(ctx, enc, &gpu, &buffer, &chain))
        });
        // Both rasters' last maps, texel by texel.
        let words = compute.read_words(ctx, maps).expect("read the chain");
        let mut d = penumbra::research::stages::raster_compute::RasterDifference::default();
        for (k, s) in samples.iter().enumerate() {
            let fixed: Vec<f32> =
                readback::read_texture(ctx, &array.texture, k as u32, 4).expect("read a map");
            d.add(
                s,
                &fixed,
                &words[k * (map_size * map_size) as usize..][..(map_size * map_size) as usize],
            );
        }
        println!(
            "raster_compute vs shadow_raster, {} {map_size}², {maps} maps: {}",
            scene.name,
            d.summary()
        );
    }
    group.finish();
}
