//! The adaptive count stages driven one by one, outside any frame: reproject_count, neighbourhood,
//! quad_count and subdivide on synthetic masks (two soft edges, stages::twin::synthetic) at 512²,
//! level 2 (16 quads); compact, probe and weights likewise at 256² (`local_stages_alone`). One iteration = one pass recorded, submitted and waited for; throughput in
//! pixel·quad evaluations (subdivide: quads).

use criterion::{BenchmarkId, Criterion, Throughput};
use penumbra::research::gpu::structs::{GpuFrame, GpuSample};
use penumbra::research::gpu::{readback, GpuContext};
use penumbra::research::methods::adaptive::buffers::{AdaptiveBuffers, Level, LATTICE_POINTS};
use penumbra::research::methods::adaptive::level_uniform;
use penumbra::research::methods::AdaptiveParams;
use penumbra::research::stages::twin::synthetic;
use penumbra::research::stages::{
    neighbourhood::Neighbourhood, quad_count::QuadCount, reproject_count::ReprojectCount,
    subdivide::Subdivide,
};
use std::time::{Duration, Instant};

const SIDE: u32 = 512;
/// Records one pass into an encoder.
type Record<'a> = &'a dyn Fn(&mut wgpu::CommandEncoder);
const LEVEL: u32 = 2;

pub fn adaptive_stages_alone(c: &mut Criterion, ctx: &GpuContext) {
    let e = synthetic::edge_masks(SIDE, SIDE, 1);
    let quads = synthetic::level_quads(LEVEL);
    let n = quads.len() as u32;
    let b = AdaptiveBuffers::new(
        ctx,
        SIDE,
        SIDE,
        &[GpuSample::default(); LATTICE_POINTS as usize],
        false,
        None,
    )
    .expect("adaptive buffers");
    ctx.queue
        .write_buffer(&b.masks.lit, 0, bytemuck::cast_slice(&e.masks));
    ctx.queue
        .write_buffer(&b.quads[0], 0, bytemuck::cast_slice(&quads));
    let frame = readback::uniform_buffer(
        ctx,
        "frame",
        &GpuFrame {
            width: SIDE,
            height: SIDE,
            ..Default::default()
        },
    );
    let uniform = readback::uniform_buffer(
        ctx,
        "level",
        &level_uniform(&AdaptiveParams::default(), b.shape, LEVEL, n, 0),
    );
    let lv = Level {
        frame: &frame,
        uniform: &uniform,
        quads: &b.quads[0],
        control: &b.control,
        cur: 0,
        shape: b.shape,
    };
    let (reproject, neighbourhood, quad_count, subdivide) = (
        ReprojectCount::new(ctx).unwrap(),
        Neighbourhood::new(ctx).unwrap(),
        QuadCount::new(ctx).unwrap(),
        Subdivide::new(ctx).unwrap(),
    );
    let pixel_quads = (SIDE * SIDE * n) as u64;
    let stages: [(&str, u64, Record); 4] = [
        ("reproject_count", pixel_quads, &|enc| {
            reproject.record_dense(ctx, enc, &lv, &b.masks, &b.counts)
        }),
        ("neighbourhood", pixel_quads, &|enc| {
            neighbourhood.record_dense(ctx, enc, &lv, &b.counts, &b.low)
        }),
        ("quad_count", pixel_quads, &|enc| {
            quad_count.record(ctx, enc, &lv, &b.low, n, None)
        }),
        // subdivide appends; clearing its counters keeps every iteration the same work.
        ("subdivide", n as u64, &|enc| {
            enc.clear_buffer(&b.control, 0, None);
            enc.clear_buffer(&b.decisions.lattice_state, 0, None);
            subdivide.record(ctx, enc, &lv, &b.low, &b.quads[1], &b.decisions)
        }),
    ];
    time_alone(
        c,
        ctx,
        "adaptive_stage_alone",
        &format!("{SIDE}x{SIDE}_{n}_quads"),
        &stages,
    );
}

const LOCAL_SIDE: u32 = 256;

/// compact (`main`), probe (`main`) and weights (`main`) driven alone, as the count stages above:
/// scope = local buffers at 256², every geometry pixel an item of each level-2 quad (counts from
/// the reproject_count twin), every other quad split; probe then tests the probes compact appended;
/// weights normalises a fixed quadtree's leaves (area rule). Appends restart every iteration.
pub fn local_stages_alone(c: &mut Criterion, ctx: &GpuContext) {
    use penumbra::research::render::gbuffer::GBufferPass;
    use penumbra::research::stages::{
        compact::{Compact, CompactInputs},
        probe::Probe,
        weights::{WeightsPass, RULE_AREA},
    };
    let side = LOCAL_SIDE;
    let e = synthetic::edge_masks(side, side, 1);
    let quads = synthetic::level_quads(LEVEL);
    let n = quads.len() as u32;
    let b = AdaptiveBuffers::new(
        ctx,
        side,
        side,
        &[GpuSample::default(); LATTICE_POINTS as usize],
        true,
        None,
    )
    .expect("adaptive buffers");
    let counts = penumbra::research::stages::twin::reproject_count::reproject_count(
        &quads,
        &e.masks,
        &e.gbuffer(),
    );
    let (split_base, next_quads) = synthetic::split(&quads, |q| q % 2 == 0);
    let items: Vec<u32> = (0..side * side)
        .filter(|&p| e.geometry[p as usize])
        .flat_map(|p| (0..n).flat_map(move |q| [p, q]))
        .collect();
    let item_count = items.len() as u32 / 2;
    ctx.queue
        .write_buffer(&b.masks.lit, 0, bytemuck::cast_slice(&e.masks));
    ctx.queue
        .write_buffer(&b.items.items[0], 0, bytemuck::cast_slice(&items));
    ctx.queue
        .write_buffer(&b.items.total, 0, bytemuck::bytes_of(&item_count));
    ctx.queue.write_buffer(
        &b.items.list_args,
        0,
        bytemuck::cast_slice(&[item_count.div_ceil(64), 1, 1]),
    );
    ctx.queue
        .write_buffer(&b.counts.maps, 0, bytemuck::cast_slice(&counts));
    ctx.queue.write_buffer(
        &b.decisions.split_base,
        0,
        bytemuck::cast_slice(&split_base),
    );
    ctx.queue
        .write_buffer(&b.quads[1], 0, bytemuck::cast_slice(&next_quads));
    let p = AdaptiveParams::default();
    let frame = readback::uniform_buffer(
        ctx,
        "frame",
        &GpuFrame {
            width: side,
            height: side,
            ..Default::default()
        },
    );
    let uniform = readback::uniform_buffer(ctx, "level", &level_uniform(&p, b.shape, LEVEL, n, 0));
    let child_uniform = readback::uniform_buffer(
        ctx,
        "level",
        &level_uniform(&p, b.shape, LEVEL + 1, next_quads.len() as u32, 0),
    );
    let lv = Level {
        frame: &frame,
        uniform: &uniform,
        quads: &b.quads[0],
        control: &b.control,
        cur: 0,
        shape: b.shape,
    };
    let child = Level {
        frame: &frame,
        uniform: &child_uniform,
        quads: &b.quads[1],
        control: &b.control,
        cur: 1,
        shape: b.shape,
    };
    let g = GBufferPass::allocate(ctx, side, side).expect("G-buffer");
    let (compact, probe) = (Compact::new(ctx).unwrap(), Probe::new(ctx).unwrap());
    let compact_inputs = CompactInputs {
        counts: &b.counts,
        decisions: &b.decisions,
        next_quads: &b.quads[1],
        samples: &b.samples,
        items: &b.items,
        footprints: &b.footprints,
    };
    let weights = WeightsPass::new(ctx, RULE_AREA).unwrap();
    // Once before timing: compact's probes become probe's work, and weights' leaves are appended.
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    enc.clear_buffer(&b.control, 0, None);
    compact.record_main(ctx, &mut enc, &lv, &g, &compact_inputs, false);
    probe.record_begin(ctx, &mut enc, &child_uniform, &b.control, &b.items);
    weights.record_begin(&mut enc);
    weights.record_leaves(ctx, &mut enc, &uniform, &b.quads[0], &b.decisions);
    ctx.queue.submit([enc.finish()]);
    let probes: Vec<u32> =
        readback::read_buffer(ctx, &b.items.probe_total, 4).expect("probe count");
    ctx.queue.write_buffer(
        &b.decisions.lattice_state,
        0,
        bytemuck::cast_slice(&[1u32; LATTICE_POINTS as usize]),
    );
    let stages: [(&str, u64, Record); 3] = [
        ("compact", item_count as u64, &|enc| {
            enc.clear_buffer(&b.control, 0, None);
            compact.record_main(ctx, enc, &lv, &g, &compact_inputs, false)
        }),
        ("probe", probes[0] as u64, &|enc| {
            enc.clear_buffer(&b.control, 0, None);
            probe.record(ctx, enc, &child, &b.masks, &b.items)
        }),
        ("weights", n as u64, &|enc| {
            weights.record(ctx, enc, &b.decisions, &b.weights)
        }),
    ];
    time_alone(
        c,
        ctx,
        "adaptive_local_stage_alone",
        &format!("{side}x{side}_{n}_quads"),
        &stages,
    );
}

/// Each stage recorded alone, submitted and waited for: wall clock per dispatch, its elements.
fn time_alone(
    c: &mut Criterion,
    ctx: &GpuContext,
    group_name: &str,
    label: &str,
    stages: &[(&str, u64, Record)],
) {
    let mut group = c.benchmark_group(group_name);
    group.sample_size(10);
    for (name, elements, record) in stages {
        group.throughput(Throughput::Elements(*elements));
        group.bench_function(BenchmarkId::new(*name, label), |bench| {
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
