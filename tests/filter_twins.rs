//! The single-map kernels equal their CPU twins on random scenes: pcf (every kernel, and seed
//! 004's settings), pcss, and the filtered maps' three stages (moments, blur, reconstruct), each
//! twin fed the GPU's own inputs so a mismatch points at one stage.

mod common;
use penumbra::research::frame::{frame_uniform, FrameOptions, FrameResult};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::{single_map, Method};
use penumbra::research::scene::Scene;
use penumbra::research::stages::twin;

fn scene(seed: u64) -> Scene {
    Scene::parse(
        &common::random_scene_toml(seed, 48, 128),
        &format!("random-{seed}"),
        None,
        &[],
    )
    .unwrap()
}

fn inspected(
    ctx: &penumbra::research::gpu::GpuContext,
    sc: &Scene,
    spec: &str,
) -> (FrameResult, single_map::SingleMapBuffers) {
    let options = FrameOptions {
        mode: TimingMode::Frame,
        pictures: false,
    };
    common::inspected(ctx, sc, &Method::parse(spec, &[]).unwrap(), options)
}

/// (pixels differing by more than `tol`, largest difference) over geometry pixels.
fn compare(gpu: &[f32], cpu: &[f32], r: &FrameResult, tol: f32) -> (usize, f32, usize) {
    let (mut off, mut worst, mut n) = (0, 0.0f32, 0);
    for i in 0..gpu.len() {
        if r.gbuffer.is_geometry(i) {
            let d = (gpu[i] - cpu[i].clamp(0.0, 1.0)).abs();
            off += (d > tol) as usize;
            worst = worst.max(d);
            n += 1;
        }
    }
    (off, worst, n)
}

#[test]
fn pcf_and_pcss_equal_their_cpu_twins() {
    let ctx = common::gpu();
    // (spec, share of pixels allowed off by more than `tol`, tol): taps on rotated disks come from
    // sin and cos, whose last bits may differ between devices and move a tap across a texel edge;
    // the comparison sampler filters with the device's own weights.
    let specs: [(&str, f64, f32); 7] = [
        ("pcf:kernel=box", 0.0, 1e-5),
        ("pcf:kernel=poisson", 0.0, 1e-5),
        ("pcf:kernel=poisson,taps=64,radius=3.5", 0.0, 1e-5),
        (
            "pcf:kernel=stratified,taps=4,spread=1/700,darkening=0.2",
            0.0,
            1e-5,
        ),
        ("pcf:kernel=rotated", 0.002, 1e-5),
        ("pcf:kernel=bilinear", 0.0, 1e-4),
        ("pcss", 0.0, 1e-5),
    ];
    for seed in [3u64, 11] {
        let sc = scene(seed);
        for (spec, share, tol) in specs {
            let (r, c) = inspected(ctx, &sc, spec);
            let fr = frame_uniform(&sc);
            let cpu = if spec.starts_with("pcss") {
                twin::pcss::pcss(&fr, &c.filter, &c.sample, &c.map, &r.gbuffer)
            } else {
                twin::pcf::pcf(&fr, &c.filter, &c.sample, &c.map, &c.disk, &r.gbuffer)
            };
            let (off, worst, n) = compare(&r.visibility, &cpu, &r, tol);
            let partial = (0..n)
                .filter(|&i| {
                    r.gbuffer.is_geometry(i) && r.visibility[i] > 0.0 && r.visibility[i] < 1.0
                })
                .count();
            println!("seed {seed} {spec}: {off}/{n} pixels off by > {tol:e}, max |GPU - twin| = {worst:e}, {partial} partly lit");
            assert!(
                partial > 20,
                "seed {seed} {spec}: only {partial} partly lit pixels, the test would prove little"
            );
            assert!(
                off as f64 <= share * n as f64,
                "seed {seed} {spec}: {off} of {n} pixels differ from the twin (max {worst})"
            );
        }
    }
}

/// Largest |a - b| / max(1, |b|) over every component.
fn rel_diff(a: &[[f32; 4]], b: &[[f32; 4]]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| (0..4).map(move |k| (x[k] - y[k]).abs() / y[k].abs().max(1.0)))
        .fold(0.0, f32::max)
}

#[test]
fn filtered_stages_equal_their_cpu_twins() {
    let ctx = common::gpu();
    for seed in [3u64, 11] {
        let sc = scene(seed);
        let fr = frame_uniform(&sc);
        for spec in ["esm", "vsm", "evsm", "msm", "csm", "csm:order=7"] {
            let (r, c) = inspected(ctx, &sc, spec);
            let f = &c.filter;
            let size = fr.map_size;
            let raw = twin::moments::moments(f, &c.sample, &c.map, size);
            // msm rounds to 16 bits: a value on a rounding edge may land one step either way.
            // exp, sin and cos may differ from the CPU's in the last bits.
            let moments_tol = if spec == "msm" { 1.5 / 65535.0 } else { 1e-5 };
            let d_moments = rel_diff(&c.raw, &raw);
            let d_h = rel_diff(
                &c.scratch,
                &twin::blur::blur(&c.raw, size, f.layers, f.blur_radius, true),
            );
            let d_v = rel_diff(
                &c.filtered,
                &twin::blur::blur(&c.scratch, size, f.layers, f.blur_radius, false),
            );
            let cpu = twin::reconstruct::reconstruct(&fr, f, &c.sample, &c.filtered, &r.gbuffer);
            // 4MSM solves a 3x3 Hankel system in f32 with heavy cancellation: last-bit differences
            // of the device's arithmetic grow to ~1e-3 there.
            let tol = if spec == "msm" { 5e-3 } else { 1e-4 };
            let (off, worst, n) = compare(&r.visibility, &cpu, &r, tol);
            println!(
                "seed {seed} {spec}: moments {d_moments:e}, blur h {d_h:e}, blur v {d_v:e} (relative); reconstruct {off}/{n} pixels off by > {tol:e}, max {worst:e}; radius {}",
                f.blur_radius
            );
            assert!(
                d_moments <= moments_tol,
                "seed {seed} {spec}: moments differ by {d_moments}"
            );
            assert!(
                d_h <= 1e-5 && d_v <= 1e-5,
                "seed {seed} {spec}: blur differs by {d_h} / {d_v}"
            );
            assert!(
                off as f64 <= 0.002 * n as f64,
                "seed {seed} {spec}: reconstruct differs in {off} of {n} pixels (max {worst})"
            );
            let partial = (0..n)
                .filter(|&i| {
                    r.gbuffer.is_geometry(i) && r.visibility[i] > 0.01 && r.visibility[i] < 0.99
                })
                .count();
            assert!(
                partial > 20,
                "seed {seed} {spec}: only {partial} partly lit pixels"
            );
        }
    }
}
