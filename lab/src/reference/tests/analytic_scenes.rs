//! The tracer against the closed forms of the analytic-square scene, and the closed form itself.

use super::*;

#[test]
fn continuous_matches_closed_form() {
    for (name, scene) in configurations() {
        let tracer = Tracer::new(&scene.triangles(20.0));
        let grid = shadow_grid(&scene, 24);
        let points: Vec<_> = grid.iter().map(|&p| ground(p)).collect();
        let mode = ReferenceMode::DEFAULT_CONTINUOUS;
        let traced = trace_visibility(
            &tracer,
            &points,
            &scene.light(),
            &mode,
            RAY_OFFSET,
            &no_progress,
        );
        let (mut sum, mut sum_pen, mut n_pen, mut max) = (0.0f64, 0.0f64, 0usize, 0.0f64);
        for (p, v) in grid.iter().zip(&traced) {
            let exact = scene.visibility(lifted(*p));
            let err = (*v as f64 - exact as f64).abs();
            sum += err;
            max = max.max(err);
            if exact > 0.0 && exact < 1.0 {
                sum_pen += err;
                n_pen += 1;
            }
        }
        let mae = sum / grid.len() as f64;
        println!(
            "continuous 32x32 {name}: MAE {mae:.2e} over {} points, MAE {:.2e} over {n_pen} penumbra points, max {max:.2e}",
            grid.len(),
            sum_pen / n_pen.max(1) as f64
        );
        assert!(
            n_pen > grid.len() / 4,
            "{name}: grid should sit mostly in the penumbra"
        );
        assert!(mae < 2e-3, "{name}: MAE {mae}");
    }
}

#[test]
fn lattice_matches_closed_form_exactly() {
    for (name, scene) in configurations() {
        let tracer = Tracer::new(&scene.triangles(20.0));
        let light = scene.light();
        // Nudge a point sideways until every lattice segment clears the occluder edges by the
        // margin: an exact tie is decided by f32 rounding, not geometry.
        let mut nudged = 0;
        let o = scene.occluder_center;
        let centred = o.x - o.z == scene.light_center.x - scene.light_center.z;
        let diagonal = (0..64).filter(|_| centred).map(|i| {
            let d = (i as f32 - 31.7) * 0.05;
            Vec3::new(o.x + d, 0.0, o.z + d)
        });
        let grid: Vec<Vec3> = shadow_grid(&scene, 24)
            .into_iter()
            .chain(diagonal)
            .map(|mut p| {
                for _ in 0..16 {
                    if scene.lattice_margin(lifted(p)) >= MIN_LATTICE_MARGIN {
                        break;
                    }
                    p.x += 3.7e-4;
                    nudged += 1;
                }
                assert!(scene.lattice_margin(lifted(p)) >= MIN_LATTICE_MARGIN);
                p
            })
            .collect();
        let points: Vec<_> = grid.iter().map(|&p| ground(p)).collect();
        let traced = trace_visibility(
            &tracer,
            &points,
            &light,
            &ReferenceMode::Lattice,
            RAY_OFFSET,
            &no_progress,
        );
        let mut partial = 0;
        for (p, v) in grid.iter().zip(&traced) {
            let exact = analytic_lattice_visibility(
                scene.light_center,
                scene.light_side,
                scene.occluder_center,
                scene.occluder_side,
                lifted(*p),
            );
            assert_eq!(*v, exact, "{name}: lattice mismatch at {p}");
            partial += (exact > 0.0 && exact < 1.0) as usize;
        }
        println!(
            "lattice {name}: {} points equal exactly ({partial} partially lit, {nudged} nudges)",
            grid.len()
        );
    }
}

#[test]
fn closed_form_limits() {
    let (_, scene) = configurations()[0];
    // Straight below a much larger occluder: umbra. Far away: fully lit.
    let big = AnalyticSquareScene {
        occluder_side: 10.0,
        ..scene
    };
    assert_eq!(big.visibility(Vec3::ZERO), 0.0);
    assert_eq!(big.lattice_visibility(Vec3::ZERO), 0.0);
    assert_eq!(scene.visibility(Vec3::new(50.0, 0.0, 0.0)), 1.0);
    assert_eq!(scene.lattice_visibility(Vec3::new(50.0, 0.0, 0.0)), 1.0);
    // Above the light: unlit.
    assert_eq!(scene.visibility(Vec3::new(0.0, 9.0, 0.0)), 0.0);
    // The lattice count converges to the area as the lattice would refine: here just bracket it.
    let p = Vec3::new(0.3, 0.0, 0.2);
    assert!((scene.visibility(p) - scene.lattice_visibility(p)).abs() < 0.15);
}

#[test]
fn closed_form_matches_a_dense_midpoint_count() {
    // Independent of the tracer and of the projection formula: test each of N×N midpoint light
    // samples against the occluder in its own plane (separable, so N + N tests per point).
    const N: usize = 4096;
    for (name, scene) in configurations() {
        let (l, o) = (
            scene.light_center.as_dvec3(),
            scene.occluder_center.as_dvec3(),
        );
        let (b, half) = (scene.light_side as f64, 0.5 * scene.occluder_side as f64);
        for p in shadow_grid(&scene, 7) {
            let p = p.as_dvec3();
            let lambda = (o.y - p.y) / (l.y - p.y);
            let inside = |pc: f64, lc: f64, oc: f64| {
                (0..N)
                    .filter(|&i| {
                        let y = lc + ((i as f64 + 0.5) / N as f64 - 0.5) * b;
                        (pc + (y - pc) * lambda - oc).abs() <= half
                    })
                    .count() as f64
                    / N as f64
            };
            let dense = 1.0 - inside(p.x, l.x, o.x) * inside(p.z, l.z, o.z);
            let exact = scene.visibility(p.as_vec3()) as f64;
            assert!(
                (dense - exact).abs() < 1e-3,
                "{name} at {p}: {dense} vs {exact}"
            );
        }
    }
}
