//! `hard` on `analytic-square` agrees with the exact geometric hard shadow (a ray from each
//! G-buffer point to the light's centre) at every geometry pixel farther than 1.5 px from its boundary.

mod common;
use glam::Vec3;
use penumbra::research::frame;
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;

/// Möller–Trumbore: does the segment origin → origin + dir (t in (0, 1)) hit the triangle?
fn hits(origin: Vec3, dir: Vec3, [a, b, c]: [Vec3; 3]) -> bool {
    let (e1, e2) = (b - a, c - a);
    let pv = dir.cross(e2);
    let det = e1.dot(pv);
    if det.abs() < 1e-12 {
        return false;
    }
    let inv = 1.0 / det;
    let tv = origin - a;
    let u = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let qv = tv.cross(e1);
    let v = dir.dot(qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let t = e2.dot(qv) * inv;
    t > 1e-4 && t < 1.0 - 1e-4
}

#[test]
fn hard_matches_the_exact_hard_shadow_away_from_its_boundary() {
    let ctx = common::gpu();
    let scene = Scene::load("analytic-square", &[]).unwrap();
    let r = frame::render(ctx, &scene, &Method::hard(), TimingMode::Frame).unwrap();
    let g = &r.gbuffer;
    let (w, h) = (g.width as i32, g.height as i32);
    let tris = scene.triangles();
    let centre = scene.light.center;
    let exact: Vec<Option<bool>> = (0..(w * h) as usize)
        .map(|i| {
            if !g.is_geometry(i) {
                return None;
            }
            let p = Vec3::from_slice(&g.position[i][..3]);
            let n = Vec3::from_slice(&g.normal[i][..3]);
            let origin = p + n * 1e-3;
            let lit =
                n.dot(centre - p) > 0.0 && !tris.iter().any(|t| hits(origin, centre - origin, *t));
            Some(lit)
        })
        .collect();
    let (mut compared, mut shadowed, mut wrong) = (0, 0, Vec::new());
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let Some(e) = exact[i] else { continue };
            // within 1.5 px: the 8-neighbourhood
            let near_boundary = (-1..=1).any(|dy| {
                (-1..=1).any(|dx| {
                    let (qx, qy) = (x + dx, y + dy);
                    qx >= 0
                        && qy >= 0
                        && qx < w
                        && qy < h
                        && matches!(exact[(qy * w + qx) as usize], Some(o) if o != e)
                })
            });
            if near_boundary {
                continue;
            }
            compared += 1;
            shadowed += (!e) as usize;
            let v = r.visibility[i];
            if v != if e { 1.0 } else { 0.0 } {
                wrong.push((x, y, e, v));
            }
        }
    }
    let geometry = g.geometry_count();
    println!("geometry pixels {geometry}, compared {compared}, exact shadow {shadowed}, disagreements {}", wrong.len());
    assert!(
        compared as f64 > 0.9 * geometry as f64,
        "too few pixels compared: {compared} of {geometry}"
    );
    assert!(
        shadowed > 500,
        "the exact shadow covers only {shadowed} compared pixels"
    );
    assert!(
        wrong.is_empty(),
        "{} pixels disagree, first: {:?}",
        wrong.len(),
        &wrong[..wrong.len().min(10)]
    );
}
