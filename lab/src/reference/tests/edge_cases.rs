//! Conventions at the edges: unlit and invalid points, watertightness, progress reports.

use super::*;
use std::sync::Mutex;

#[test]
fn unoccluded_is_fully_lit_even_with_the_light_quad_in_the_scene() {
    let light = RefLight {
        center: Vec3::new(0.2, 3.0, -0.1),
        edge_u: Vec3::X,
        edge_v: Vec3::Z * 0.5,
    };
    // The emitter itself is geometry here: LIGHT_END_EPS keeps it from shadowing its own samples.
    let mut tris = AnalyticSquareScene {
        light_center: light.center,
        light_side: 1.0,
        occluder_center: Vec3::new(0.0, 1.0, 0.0),
        occluder_side: 0.0,
    }
    .triangles(10.0);
    tris.truncate(2); // ground only
    let (c, u, v) = (light.center, light.edge_u * 0.5, light.edge_v * 0.5);
    tris.push([c - u - v, c + u - v, c + u + v]);
    tris.push([c - u - v, c + u + v, c - u + v]);
    let tracer = Tracer::new(&tris);
    let points: Vec<_> = (0..50)
        .map(|i| ground(Vec3::new(i as f32 * 0.17 - 4.0, 0.0, 0.3)))
        .collect();
    for mode in [
        ReferenceMode::Lattice,
        ReferenceMode::Continuous { m: 8, seed: 1 },
    ] {
        let v = trace_visibility(&tracer, &points, &light, &mode, RAY_OFFSET, &no_progress);
        assert!(v.iter().all(|&x| x == 1.0), "{mode:?}: {v:?}");
    }
}

#[test]
fn unlit_background_and_bad_points_are_zero_never_nan() {
    let tracer = Tracer::new(&[]);
    let light = RefLight {
        center: Vec3::new(0.0, 3.0, 0.0),
        edge_u: Vec3::X,
        edge_v: Vec3::Z,
    };
    let points = [
        None,
        Some(SurfacePoint {
            position: Vec3::new(0.0, 5.0, 0.0),
            normal: Vec3::Y,
        }), // behind light
        Some(SurfacePoint {
            position: Vec3::new(0.0, 3.0, 0.0),
            normal: Vec3::Y,
        }), // in its plane
        Some(SurfacePoint {
            position: Vec3::ZERO,
            normal: -Vec3::Y,
        }), // faces away
        Some(SurfacePoint {
            position: Vec3::splat(f32::NAN),
            normal: Vec3::Y,
        }),
        Some(SurfacePoint {
            position: Vec3::ZERO,
            normal: Vec3::ZERO,
        }),
        Some(SurfacePoint {
            position: Vec3::ZERO,
            normal: Vec3::Y * 7.0,
        }), // unnormalised: fine
    ];
    for mode in [ReferenceMode::Lattice, ReferenceMode::DEFAULT_CONTINUOUS] {
        let v = trace_visibility(&tracer, &points, &light, &mode, RAY_OFFSET, &no_progress);
        assert_eq!(v, vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0], "{mode:?}");
    }
    // A wall through the light's centre line sees the 8 lattice columns strictly in front of it;
    // the column in its tangent plane counts as blocked.
    let wall = [Some(SurfacePoint {
        position: Vec3::new(0.0, 2.0, 0.0),
        normal: -Vec3::X,
    })];
    let v = trace_visibility(
        &tracer,
        &wall,
        &light,
        &ReferenceMode::Lattice,
        RAY_OFFSET,
        &no_progress,
    );
    assert_eq!(v[0], (8 * 17) as f32 / 289.0);
}

#[test]
fn invalid_input_is_an_error_or_zeros() {
    let tracer = Tracer::new(&[]);
    let flat = RefLight {
        center: Vec3::Y,
        edge_u: Vec3::X,
        edge_v: Vec3::X,
    };
    let pts = [ground(Vec3::ZERO)];
    assert!(matches!(
        try_trace_visibility(
            &tracer,
            &pts,
            &flat,
            &ReferenceMode::Lattice,
            0.0,
            &no_progress
        ),
        Err(ReferenceError::DegenerateLight)
    ));
    let light = RefLight {
        center: Vec3::Y,
        edge_u: Vec3::X,
        edge_v: Vec3::Z,
    };
    let none = ReferenceMode::Continuous { m: 0, seed: 0 };
    assert!(matches!(
        try_trace_visibility(&tracer, &pts, &light, &none, 0.0, &no_progress),
        Err(ReferenceError::NoSamples)
    ));
    assert_eq!(
        trace_visibility(&tracer, &pts, &light, &none, 0.0, &no_progress),
        vec![0.0]
    );
    // Non-finite triangles are dropped, not fed to the BVH builder.
    let t = Tracer::new(&[
        [Vec3::NAN, Vec3::X, Vec3::Z],
        [Vec3::ZERO, Vec3::X, Vec3::Z],
    ]);
    assert_eq!(t.skipped_triangles(), 1);
}

#[test]
fn shared_edges_are_watertight() {
    // Rays aimed exactly at points of the occluder's shared diagonal and at its centre vertex fan.
    let (_, scene) = configurations()[0];
    let mut tris = scene.triangles(20.0);
    let o = scene.occluder_center;
    let h = 0.5 * scene.occluder_side;
    let fan_centre = o + Vec3::new(0.0, 1.0, 0.0);
    for (a, b) in [(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .zip([(1.0f32, -1.0f32), (1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0)].iter())
    {
        let p = |c: &(f32, f32)| fan_centre + Vec3::new(c.0 * h, 0.0, c.1 * h);
        tris.push([fan_centre, p(a), p(b)]);
    }
    let tracer = Tracer::new(&tris);
    let mut rng = sampling::PixelRng::new(42, 0);
    let (mut misses, n) = (0, 20_000);
    for i in 0..n {
        let origin = Vec3::new(rng.next_f32() * 4.0 - 2.0, 0.01, rng.next_f32() * 4.0 - 2.0);
        let target = if i % 2 == 0 {
            let s = rng.next_f32() * 2.0 - 1.0; // on the diagonal (-h,-h)..(h,h)
            o + Vec3::new(s * h, 0.0, s * h)
        } else {
            fan_centre
        };
        let d = target - origin;
        misses += !tracer.occluded(origin, d, 2.0) as usize; // t in units of |d|: past the target
    }
    assert_eq!(misses, 0, "rays slipped through shared edges");
    assert_eq!(tracer.rays_traced(), n as u64);
}

#[test]
fn axis_aligned_and_negative_zero_directions_hit() {
    let tracer = Tracer::new(
        &AnalyticSquareScene {
            light_center: Vec3::Y * 3.0,
            light_side: 1.0,
            occluder_center: Vec3::Y,
            occluder_side: 1.0,
        }
        .triangles(10.0),
    );
    let o = Vec3::new(0.1, 2.0, 0.2);
    // `-Vec3::Y` is (-0, -1, -0): obvhs alone misses the whole scene with it.
    for d in [
        -Vec3::Y,
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::new(-0.0, -1.0, 0.0),
    ] {
        let hit = tracer.closest_hit(o, d, f32::INFINITY);
        assert_eq!(hit.map(|h| h.t), Some(1.0), "{d:?}");
        assert!(tracer.occluded(o, d, 1.5), "{d:?}");
        assert!(!tracer.occluded(o, d, 0.5), "t_max bounds the segment");
    }
    let up = tracer.closest_hit(Vec3::new(0.1, -1.0, 0.2), Vec3::Y, f32::INFINITY);
    assert_eq!(
        up.map(|h| h.t),
        Some(1.0),
        "two-sided: ground hit from below"
    );
}

#[test]
fn progress_reports_every_pixel() {
    let (_, scene) = configurations()[1];
    let tracer = Tracer::new(&scene.triangles(20.0));
    let points: Vec<_> = shadow_grid(&scene, 40).into_iter().map(ground).collect();
    let reports = Mutex::new(Vec::new());
    let progress = |n: usize| reports.lock().expect("no panics while held").push(n);
    let mode = ReferenceMode::Continuous { m: 4, seed: 3 };
    let a = trace_visibility(
        &tracer,
        &points,
        &scene.light(),
        &mode,
        RAY_OFFSET,
        &progress,
    );
    let b = trace_visibility(
        &tracer,
        &points,
        &scene.light(),
        &mode,
        RAY_OFFSET,
        &no_progress,
    );
    assert_eq!(a, b, "deterministic across runs and thread schedules");
    let reports = reports.into_inner().expect("not poisoned");
    assert_eq!(reports.len(), points.len().div_ceil(256), "once per chunk");
    assert!(
        reports.windows(2).all(|w| w[0] < w[1]),
        "monotonic: {reports:?}"
    );
    assert_eq!(reports.last(), Some(&points.len()));
}
