//! Which triangles a kept map's redrawn rectangle needs (docs/reuse.md §2). A rectangle a moved
//! mesh touched is cleared to the far plane and drawn again; every triangle that covers a texel
//! centre inside it must be drawn, and no other can change a texel there. A triangle whose three
//! vertices lie outside one side of the rectangle's pyramid (the four planes through the light
//! sample and the rectangle's edges, widened by `MARGIN` texels) covers none of its texels, so the
//! redraw draws only the others: on a CPU device the full scene's vertex and setup work per map is
//! most of a redraw, where the rectangle is a few per cent of the map's texels.
//!
//! The test is conservative whatever the projection: the set of points that project into the
//! rectangle in front of the sample is the intersection of four half-spaces (`X - x0 W >= 0`, ...),
//! a convex set, and a triangle entirely outside one of them misses it whatever the clipping.

use glam::{Mat4, Vec3, Vec4};

/// Texels added around the rectangle before the test, far above the CPU's and the raster's
/// rounding of a vertex's position (a vertex is snapped by a fraction of a texel).
pub(crate) const MARGIN: f32 = 2.0;

/// The four planes (world space, `plane · (p, 1) >= 0` inside) of the pyramid through the texels
/// `[x, y, w, h]` of a `size`² map whose clip-from-world matrix is `m` (texel y runs down, as the
/// scissor and `MapKey::footprint` count it).
pub(crate) fn planes(m: Mat4, size: u32, rect: [u32; 4]) -> [Vec4; 4] {
    let s = size as f32;
    let [x, y, w, h] = rect.map(|v| v as f32);
    let x0 = 2.0 * (x - MARGIN) / s - 1.0;
    let x1 = 2.0 * (x + w + MARGIN) / s - 1.0;
    // Texel row t is NDC y = 1 - 2 t / size.
    let y_top = 1.0 - 2.0 * (y - MARGIN) / s;
    let y_bottom = 1.0 - 2.0 * (y + h + MARGIN) / s;
    let (rx, ry, rw) = (m.row(0), m.row(1), m.row(3));
    [
        rx - x0 * rw,
        x1 * rw - rx,
        ry - y_bottom * rw,
        y_top * rw - ry,
    ]
}

/// Whether every point of the box lies outside one of the planes.
fn box_outside(planes: &[Vec4; 4], lo: Vec3, hi: Vec3) -> bool {
    planes.iter().any(|p| {
        // The corner furthest along the plane's normal.
        let far = Vec3::select(p.truncate().cmpge(Vec3::ZERO), hi, lo);
        p.truncate().dot(far) + p.w < 0.0
    })
}

/// Appends to `out` the triangles of `order` (three indices each, grouped in runs of `run`
/// triangles whose boxes `boxes` holds) that may cover a texel of the rectangle.
pub(crate) fn triangles(
    planes: &[Vec4; 4],
    positions: &[Vec3],
    order: &[u32],
    boxes: &[[Vec3; 2]],
    run: usize,
    out: &mut Vec<u32>,
) {
    for (r, tris) in order.chunks(3 * run).enumerate() {
        let [lo, hi] = boxes[r];
        if box_outside(planes, lo, hi) {
            continue;
        }
        for t in tris.chunks_exact(3) {
            let v = [t[0], t[1], t[2]].map(|i| positions[i as usize].extend(1.0));
            let outside = planes.iter().any(|p| v.iter().all(|q| p.dot(*q) < 0.0));
            if !outside {
                out.extend_from_slice(t);
            }
        }
    }
}

/// The box of each run of `run` triangles of `order`.
pub(crate) fn run_boxes(positions: &[Vec3], order: &[u32], run: usize) -> Vec<[Vec3; 2]> {
    order
        .chunks(3 * run)
        .map(|tris| {
            tris.iter().fold(
                [Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)],
                |[lo, hi], &i| [lo.min(positions[i as usize]), hi.max(positions[i as usize])],
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether the texel centre (cx, cy) lies in the projection of the triangle (all in front).
    fn covers(m: Mat4, size: u32, tri: [Vec3; 3], cx: f32, cy: f32) -> bool {
        let p = tri.map(|v| {
            let c = m * v.extend(1.0);
            let s = size as f32;
            glam::Vec2::new((c.x / c.w + 1.0) * 0.5 * s, (1.0 - c.y / c.w) * 0.5 * s)
        });
        let e = |a: glam::Vec2, b: glam::Vec2| (b - a).perp_dot(glam::Vec2::new(cx, cy) - a);
        let (d0, d1, d2) = (e(p[0], p[1]), e(p[1], p[2]), e(p[2], p[0]));
        (d0 >= 0.0 && d1 >= 0.0 && d2 >= 0.0) || (d0 <= 0.0 && d1 <= 0.0 && d2 <= 0.0)
    }

    #[test]
    fn every_triangle_left_out_covers_no_texel_of_the_rectangle() {
        // A light sample 10 above the origin looking down, a 64² map; triangles scattered below.
        // Clip x = f x, y = f z, w = 10 - y (depth plays no part in the test).
        let f = 1.0 / 0.6f32.tan();
        let m = Mat4::from_cols_array_2d(&[
            [f, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.5, -1.0],
            [0.0, f, 0.0, 0.0],
            [0.0, 0.0, 0.0, 10.0],
        ]);
        let size = 64;
        let mut positions = Vec::new();
        let mut seed = 7u32;
        let mut rand = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        for _ in 0..3 * 600 {
            let c = Vec3::new(rand() * 12.0 - 6.0, rand() * 4.0, rand() * 12.0 - 6.0);
            positions.push(c);
        }
        // Triangles of nearby vertices (small) and a few spanning ones (large).
        let mut order: Vec<u32> = Vec::new();
        for t in 0..600u32 {
            let a = 3 * t;
            let (b, c) = if t % 50 == 0 {
                ((a + 301) % 1800, (a + 907) % 1800)
            } else {
                (a + 1, a + 2)
            };
            positions[b as usize] = positions[a as usize]
                + (positions[b as usize] - positions[a as usize])
                    * if t % 50 == 0 { 1.0 } else { 0.08 };
            positions[c as usize] = positions[a as usize]
                + (positions[c as usize] - positions[a as usize])
                    * if t % 50 == 0 { 1.0 } else { 0.08 };
            order.extend([a, b, c]);
        }
        let boxes = run_boxes(&positions, &order, 32);
        let rect = [20, 24, 9, 7];
        let mut kept = Vec::new();
        triangles(
            &planes(m, size, rect),
            &positions,
            &order,
            &boxes,
            32,
            &mut kept,
        );
        let kept: std::collections::HashSet<[u32; 3]> =
            kept.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        let (mut hits, mut left_out) = (0, 0);
        for t in order.chunks_exact(3) {
            let tri = [t[0], t[1], t[2]].map(|i| positions[i as usize]);
            let hit = (rect[1]..rect[1] + rect[3]).any(|y| {
                (rect[0]..rect[0] + rect[2])
                    .any(|x| covers(m, size, tri, x as f32 + 0.5, y as f32 + 0.5))
            });
            let k = kept.contains(&[t[0], t[1], t[2]]);
            assert!(
                k || !hit,
                "triangle {t:?} covers the rectangle but was left out"
            );
            hits += usize::from(hit);
            left_out += usize::from(!k);
        }
        // The test is not empty either way: some triangles cover it, most are left out.
        assert!(hits >= 5, "{hits} triangles cover the rectangle");
        assert!(left_out >= 400, "{left_out} of 600 left out");
    }
}
