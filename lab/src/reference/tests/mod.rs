//! Validation of the reference, moved with the module. Figures print with
//! `cargo test --release -- --nocapture`.

mod analytic_scenes;
mod edge_cases;
mod throughput;

use super::*;
use glam::Vec3;

pub(super) const RAY_OFFSET: f32 = 1e-3;
/// Lattice segments closer than this to an occluder edge are too close to call in f32.
pub(super) const MIN_LATTICE_MARGIN: f64 = 1e-4;

pub(super) fn no_progress(_: usize) {}

pub(super) fn ground(p: Vec3) -> Option<SurfacePoint> {
    Some(SurfacePoint {
        position: p,
        normal: Vec3::Y,
    })
}

/// Sizes and heights chosen so the penumbra is wide (A), the occluder low and small (B), the
/// occluder bigger than the light and close to it (C), and the centres aligned (D). Edge
/// positions are off the lattice, and `lattice_margin` checks every point anyway.
pub(super) fn configurations() -> Vec<(&'static str, AnalyticSquareScene)> {
    let s = |l: [f32; 3], b, o: [f32; 3], a| AnalyticSquareScene {
        light_center: Vec3::from(l),
        light_side: b,
        occluder_center: Vec3::from(o),
        occluder_side: a,
    };
    vec![
        (
            "A wide penumbra",
            s([0.0, 4.0, 0.0], 1.0, [0.1, 2.0, -0.05], 0.7),
        ),
        (
            "B low occluder",
            s([0.3, 5.0, -0.2], 2.0, [-0.2, 0.6, 0.15], 0.45),
        ),
        (
            "C big occluder near light",
            s([-0.5, 3.0, 0.4], 0.6, [0.0, 2.5, 0.1], 1.3),
        ),
        // Centres on one vertical: from points with x - z = const, the segments to the lattice
        // diagonal s = t run exactly along the occluder's shared triangle edge.
        (
            "D centred",
            s([0.25, 4.0, 0.25], 1.0, [0.25, 2.0, 0.25], 0.7),
        ),
    ]
}

/// Ground points covering the shadow and penumbra of `scene` (region where the projected occluder
/// meets the light, plus 10%), on an n×n grid with an irrational-ish phase.
pub(super) fn shadow_grid(scene: &AnalyticSquareScene, n: usize) -> Vec<Vec3> {
    let k = (scene.light_center.y / scene.occluder_center.y) as f64;
    let half = (k * scene.occluder_side as f64 + scene.light_side as f64) / (2.0 * (k - 1.0)) * 1.1;
    let centre = |o: f32, l: f32| (o as f64 * k - l as f64) / (k - 1.0);
    let (cx, cz) = (
        centre(scene.occluder_center.x, scene.light_center.x),
        centre(scene.occluder_center.z, scene.light_center.z),
    );
    let mut pts = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            let u = (i as f64 + 0.371) / n as f64 * 2.0 - 1.0;
            let v = (j as f64 + 0.629) / n as f64 * 2.0 - 1.0;
            pts.push(Vec3::new(
                (cx + u * half) as f32,
                0.0,
                (cz + v * half) as f32,
            ));
        }
    }
    pts
}

pub(super) fn lifted(p: Vec3) -> Vec3 {
    p + Vec3::Y * RAY_OFFSET // the tracer's ray origin
}
