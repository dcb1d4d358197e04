//! Rays per second on a ~50k-triangle scene (printed; asserts only sanity).

use super::*;
use std::time::Instant;

/// UV sphere of `rings × segments` quads (two triangles each, poles included).
fn uv_sphere(centre: Vec3, r: f32, rings: u32, segments: u32) -> Vec<[Vec3; 3]> {
    use std::f32::consts::{PI, TAU};
    let at = |i: u32, j: u32| {
        let (th, ph) = (
            PI * i as f32 / rings as f32,
            TAU * j as f32 / segments as f32,
        );
        centre + r * Vec3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin())
    };
    let mut tris = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            tris.push([a, b, c]);
            tris.push([a, c, d]);
        }
    }
    tris
}

#[test]
fn throughput_sphere_over_plane() {
    let mut tris = uv_sphere(Vec3::new(0.0, 1.2, 0.0), 1.0, 160, 156);
    tris.extend(
        AnalyticSquareScene {
            light_center: Vec3::ZERO,
            light_side: 1.0,
            occluder_center: Vec3::Y,
            occluder_side: 0.0,
        }
        .triangles(10.0)
        .into_iter()
        .take(2),
    );
    let t0 = Instant::now();
    let tracer = Tracer::new(&tris);
    let build = t0.elapsed();
    // Orthographic G-buffer from above, 128×128 over [-2,2]², via closest hits.
    let res = 128;
    let points: Vec<Option<SurfacePoint>> = (0..res * res)
        .map(|k| {
            let (x, y) = (k % res, k / res);
            let o = Vec3::new(
                ((x as f32 + 0.5) / res as f32) * 4.0 - 2.0,
                10.0,
                ((y as f32 + 0.5) / res as f32) * 4.0 - 2.0,
            );
            let hit = tracer.closest_hit(o, -Vec3::Y, f32::INFINITY)?;
            let n = if hit.normal.y < 0.0 {
                -hit.normal
            } else {
                hit.normal
            };
            Some(SurfacePoint {
                position: o - Vec3::Y * hit.t,
                normal: n,
            })
        })
        .collect();
    let light = RefLight {
        center: Vec3::new(0.5, 4.0, 0.3),
        edge_u: Vec3::X * 1.5,
        edge_v: Vec3::Z * 1.5,
    };
    let mode = ReferenceMode::Continuous { m: 8, seed: 9 };
    let before = tracer.rays_traced();
    let t1 = Instant::now();
    let v = trace_visibility(&tracer, &points, &light, &mode, RAY_OFFSET, &no_progress);
    let secs = t1.elapsed().as_secs_f64();
    let rays = tracer.rays_traced() - before;
    let threads = rayon::current_num_threads();
    println!(
        "throughput: {} triangles, BVH build {:.0} ms; {res}x{res} points, 8x8 samples: {rays} rays in {:.3} s = {:.2} Mrays/s on {threads} threads ({:.2} Mrays/s/thread); mean V {:.3}",
        tris.len(),
        build.as_secs_f64() * 1e3,
        secs,
        rays as f64 / secs / 1e6,
        rays as f64 / secs / 1e6 / threads as f64,
        v.iter().sum::<f32>() / v.len() as f32,
    );
    assert!(v.iter().all(|x| x.is_finite() && (0.0..=1.0).contains(x)));
    assert!(v.iter().any(|&x| x < 0.5), "sphere should cast a shadow");
}
