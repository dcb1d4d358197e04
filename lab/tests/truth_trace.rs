//! truth_trace (the GPU's exact truth at pixels) against its twin, the lab's CPU reference at the
//! same pixels, on every light kind: the same stratified samples with the same per-pixel seed,
//! so the lit count at each pixel is the same, sample for sample. What could differ is named:
//! rays a tie in f32 decided (an edge function exactly 0, which the CPU settles in f64: the
//! kernel counts them), and on the disk, the sun and the spheres the unit-disk map's cos and sin,
//! which WGSL need not round as the CPU's libm does. On lavapipe neither happens on these scenes:
//! every count is equal, and the tests hold them so.

mod common;
use penumbra::research::certify::truth::{self as gpu_truth, TruthSamples, TruthTracer};
use penumbra::research::frame;
use penumbra::research::scene::Scene;
use penumbra_lab::reference::truth::{self, Cache};
use penumbra_lab::reference::ReferenceMode;

/// (samples that differ, samples traced, ties the kernel counted) over every geometry pixel.
fn twin(scene: &Scene, mode: ReferenceMode, samples: TruthSamples) -> (u64, u64, u64, usize) {
    let ctx = common::gpu();
    let g = frame::gbuffer_only(ctx, scene).unwrap();
    let cpu = truth::compute(scene, &g, mode, &Cache::Off).unwrap();
    let tracer = TruthTracer::new(ctx, scene).unwrap();
    let pixels: Vec<u32> = (0..g.position.len() as u32)
        .filter(|&i| g.is_geometry(i as usize))
        .collect();
    let points: Vec<_> = pixels.iter().map(|&p| gpu_truth::point_of(&g, p)).collect();
    let counts = tracer.trace(ctx, &samples, &points, &|_| {}).unwrap();
    let spp = samples.per_pixel() as f64;
    let mut differ = 0u64;
    let mut pixels_differ = 0usize;
    for (k, &p) in pixels.iter().enumerate() {
        let (a, b) = (counts.visibility(k), cpu.values[p as usize]);
        if a != b {
            pixels_differ += 1;
            differ += ((a as f64 - b as f64).abs() * spp).round() as u64;
        }
    }
    (differ, counts.rays(), counts.ties(), pixels_differ)
}

fn load(name: &str) -> Scene {
    Scene::load(name, &[("resolution".into(), "64".into())]).unwrap()
}

#[test]
fn the_rectangle_is_traced_as_the_reference_traces_it() {
    for name in ["analytic-square", "default", "slat-roof"] {
        let scene = load(name);
        let (differ, rays, ties, pixels) = twin(
            &scene,
            ReferenceMode::DEFAULT_CONTINUOUS,
            gpu_truth::REFERENCE_SAMPLES,
        );
        println!("{name}: {differ} of {rays} rays differ ({pixels} pixels), {ties} ties");
        assert!(rays > 1_000_000, "{name}: only {rays} rays");
        assert_eq!(
            (differ, ties),
            (0, 0),
            "{name}: {differ} samples differ at {pixels} pixels ({ties} ties)"
        );
    }
    // The lattice, as the exact visibility at a grid's points.
    let scene = load("analytic-square");
    let (differ, rays, _, _) = twin(&scene, ReferenceMode::Lattice, TruthSamples::Lattice);
    assert!(rays > 300_000);
    assert_eq!(differ, 0);
}

#[test]
fn every_other_kind_is_traced_as_the_reference_traces_it() {
    // spot-edge at 48² holds the ray through an occluder's open edge that the CPU tracer's box test
    // once culled (one sample of 2.3 M; its boxes are padded since, lab/src/reference/tracer.rs).
    for (name, size) in [
        ("disk-bar", "64"),
        ("sun-edge", "64"),
        ("point-edge", "64"),
        ("spot-edge", "64"),
        ("spot-edge", "48"),
    ] {
        let scene = Scene::load(name, &[("resolution".into(), size.into())]).unwrap();
        let (differ, rays, ties, pixels) = twin(
            &scene,
            ReferenceMode::DEFAULT_CONTINUOUS,
            gpu_truth::REFERENCE_SAMPLES,
        );
        println!(
            "{name} at {size}²: {differ} of {rays} rays differ ({pixels} pixels), {ties} ties"
        );
        assert!(rays > 1_000_000, "{name}: only {rays} rays");
        assert_eq!(
            (differ, ties),
            (0, 0),
            "{name} at {size}²: {differ} of {rays} samples differ at {pixels} pixels ({ties} ties)"
        );
    }
    // The lattice of the kinds whose lattice is the unit square's (the point and the spot take
    // their maps' own points, which the CPU tracer alone traces).
    for name in ["disk-bar", "sun-edge"] {
        let (differ, rays, _, _) = twin(&load(name), ReferenceMode::Lattice, TruthSamples::Lattice);
        assert!(rays > 300_000, "{name}: {rays}");
        assert_eq!(differ, 0, "{name}");
    }
}
