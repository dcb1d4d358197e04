//! The adaptive count stages driven one by one, outside any frame: reproject_count, neighbourhood,
//! quad_count and subdivide on synthetic masks (two soft edges, stages::twin::synthetic) at 512²,
//! level 2 (16 quads). One iteration = one pass recorded, submitted and waited for; throughput in
//! pixel·quad evaluations (subdivide: quads).

use criterion::{BenchmarkId, Criterion, Throughput};
use penumbra::gpu::structs::{GpuFrame, GpuSample};
use penumbra::gpu::{readback, GpuContext};
use penumbra::methods::adaptive::buffers::{AdaptiveBuffers, Level, LATTICE_POINTS};
use penumbra::methods::adaptive::level_uniform;
use penumbra::methods::AdaptiveParams;
use penumbra::stages::twin::synthetic;
use penumbra::stages::{neighbourhood::Neighbourhood, quad_count::QuadCount, reproject_count::ReprojectCount, subdivide::Subdivide};
use std::time::{Duration, Instant};

const SIDE: u32 = 512;
/// Records one pass into an encoder.
type Record<'a> = &'a dyn Fn(&mut wgpu::CommandEncoder);
const LEVEL: u32 = 2;

pub fn adaptive_stages_alone(c: &mut Criterion, ctx: &GpuContext) {
    let e = synthetic::edge_masks(SIDE, SIDE, 1);
    let quads = synthetic::level_quads(LEVEL);
    let n = quads.len() as u32;
    let b = AdaptiveBuffers::new(ctx, SIDE, SIDE, &[GpuSample::default(); LATTICE_POINTS as usize], false, None).expect("adaptive buffers");
    ctx.queue.write_buffer(&b.masks.lit, 0, bytemuck::cast_slice(&e.masks));
    ctx.queue.write_buffer(&b.quads[0], 0, bytemuck::cast_slice(&quads));
    let frame = readback::uniform_buffer(ctx, "frame", &GpuFrame { width: SIDE, height: SIDE, ..Default::default() });
    let uniform = readback::uniform_buffer(ctx, "level", &level_uniform(&AdaptiveParams::default(), b.shape, LEVEL, n, 0));
    let lv = Level { frame: &frame, uniform: &uniform, quads: &b.quads[0], shape: b.shape };
    let (reproject, neighbourhood, quad_count, subdivide) =
        (ReprojectCount::new(ctx).unwrap(), Neighbourhood::new(ctx).unwrap(), QuadCount::new(ctx).unwrap(), Subdivide::new(ctx).unwrap());
    let pixel_quads = (SIDE * SIDE * n) as u64;
    let stages: [(&str, u64, Record); 4] = [
        ("reproject_count", pixel_quads, &|enc| reproject.record_dense(ctx, enc, &lv, &b.masks, &b.control, &b.counts)),
        ("neighbourhood", pixel_quads, &|enc| neighbourhood.record_dense(ctx, enc, &lv, &b.counts, &b.low)),
        ("quad_count", pixel_quads, &|enc| quad_count.record(ctx, enc, &lv, &b.low, n, None)),
        // subdivide appends; clearing its counters keeps every iteration the same work.
        ("subdivide", n as u64, &|enc| {
            enc.clear_buffer(&b.control, 0, None);
            enc.clear_buffer(&b.decisions.lattice_state, 0, None);
            subdivide.record(ctx, enc, &lv, &b.low, &b.quads[1], &b.control, &b.decisions)
        }),
    ];
    let mut group = c.benchmark_group("adaptive_stage_alone");
    group.sample_size(10);
    for (name, elements, record) in stages {
        group.throughput(Throughput::Elements(elements));
        group.bench_function(BenchmarkId::new(name, format!("{SIDE}x{SIDE}_{n}_quads")), |bench| {
            bench.iter_custom(|iters| {
                let start = Instant::now();
                for _ in 0..iters {
                    let mut enc = ctx.device.create_command_encoder(&Default::default());
                    record(&mut enc);
                    ctx.queue.submit([enc.finish()]);
                    ctx.wait().expect("device wait");
                }
                start.elapsed().max(Duration::from_nanos(1))
            })
        });
    }
    group.finish();
}
