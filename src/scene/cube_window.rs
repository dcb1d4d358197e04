//! The window of a point light's cube face, fitted to the receivers the face serves.
//!
//! A receiver `p` is looked up on the face whose axis dominates `p − c` (`c` the sphere's centre,
//! `cube_face`), so face f serves the part of the scene's bounds inside f's pyramid from `c`: the
//! points whose direction from `c` has f's axis dominant. Its map looks from the face's light point
//! `y` (within the radius of `c`), so the window only has to hold that part as `y` sees it; every
//! occluder between `y` and a receiver projects inside it too. A symmetric 90° face gives a scene
//! far from the light a few texels (a light 1000 units above a 53-unit scene saw it in about 15 of
//! 512 texels a side, and every method cast the same wrong shadow); the fitted window gives it the
//! whole map (docs/lights.md, "Cube maps for the point").

use super::bounds::Bounds;
use glam::{Mat4, Vec3};

/// A face's window in tangent units of its view from `y`: x in [l, r], y in [b, t].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Window {
    pub(crate) l: f32,
    pub(crate) r: f32,
    pub(crate) b: f32,
    pub(crate) t: f32,
}

/// The symmetric 90° face: what a face gets where the fit cannot help (the light inside the
/// bounds, or a face that serves no part of them).
pub(crate) const FULL: Window = Window {
    l: -1.0,
    r: 1.0,
    b: -1.0,
    t: 1.0,
};

/// The axes of face `face` (0..5: +x, −x, +y, −y, +z, −z): forward and the two across it.
fn face_axes(face: u32) -> (Vec3, Vec3, Vec3) {
    let axes = [Vec3::X, Vec3::Y, Vec3::Z];
    let a = (face / 2) as usize;
    let forward = if face % 2 == 0 { axes[a] } else { -axes[a] };
    (forward, axes[(a + 1) % 3], axes[(a + 2) % 3])
}

/// Whether `p` lies in face `face`'s pyramid from `c`, with a tolerance `eps` (wider, never narrower).
fn in_pyramid(p: Vec3, c: Vec3, face: u32, eps: f32) -> bool {
    let (f, u, v) = face_axes(face);
    let d = p - c;
    let along = d.dot(f);
    along + eps >= d.dot(u).abs() && along + eps >= d.dot(v).abs()
}

fn in_box(p: Vec3, b: &Bounds, eps: f32) -> bool {
    p.cmpge(b.min - Vec3::splat(eps)).all() && p.cmple(b.max + Vec3::splat(eps)).all()
}

/// The vertices of the bounds clipped to face `face`'s pyramid from `c` (a convex set, so the
/// extremes of its projection lie among them): the box's corners inside the pyramid, its edges'
/// crossings of the pyramid's four side planes, and the pyramid's four edge rays' crossings of the
/// box's faces.
pub(crate) fn clipped_vertices(c: Vec3, face: u32, b: &Bounds) -> Vec<Vec3> {
    let eps = b.diagonal().max(1e-6) * 1e-5;
    let corners = b.corners();
    let mut out: Vec<Vec3> = corners
        .iter()
        .copied()
        .filter(|&p| in_pyramid(p, c, face, eps))
        .collect();
    let (f, u, v) = face_axes(face);
    // The side planes: (p − c)·n = 0.
    let planes = [f - u, f + u, f - v, f + v];
    for i in 0..8 {
        for j in i + 1..8 {
            // Box edges join corners that differ in one coordinate.
            let (a, z) = (corners[i], corners[j]);
            if (a - z).cmpne(Vec3::ZERO).bitmask().count_ones() != 1 {
                continue;
            }
            for n in planes {
                let (da, dz) = ((a - c).dot(n), (z - c).dot(n));
                if (da < 0.0) != (dz < 0.0) && da != dz {
                    let p = a + (z - a) * (da / (da - dz));
                    if in_pyramid(p, c, face, eps) {
                        out.push(p);
                    }
                }
            }
        }
    }
    for (su, sv) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
        let dir = f + u * su + v * sv;
        for axis in 0..3 {
            if dir[axis] == 0.0 {
                continue;
            }
            for plane in [b.min[axis], b.max[axis]] {
                let s = (plane - c[axis]) / dir[axis];
                let p = c + dir * s;
                if s >= 0.0 && in_box(p, b, eps) {
                    out.push(p);
                }
            }
        }
    }
    out
}

/// Face `face`'s window as `view` (the face's view from `y`) sees the part of `bounds` it serves,
/// `c` the sphere's centre, within the 90° face: never wider. (Seen from a light point off the
/// centre, receivers close to the light reach past 45°; a window stretched to them had coarser
/// texels than the 90° face and, since the lookup's bias is in texels, a larger bias: on
/// `point-edge` that leaked light along the occluder's edge and doubled `regular:n=8`'s error.
/// Those receivers take the edge texel, as on the 90° face.) [`FULL`] where the face serves
/// nothing, or where that part reaches behind `y` (the light inside or at the bounds).
pub(crate) fn fitted(c: Vec3, face: u32, bounds: &Bounds, view: &Mat4) -> Window {
    if in_box(c, bounds, 0.0) {
        return FULL;
    }
    let points = clipped_vertices(c, face, bounds);
    if points.is_empty() {
        return FULL;
    }
    let mut w = Window {
        l: f32::INFINITY,
        r: f32::NEG_INFINITY,
        b: f32::INFINITY,
        t: f32::NEG_INFINITY,
    };
    for p in points {
        let q = view.transform_point3(p);
        let depth = -q.z;
        if !(depth > 0.0) {
            return FULL;
        }
        let (x, y) = (q.x / depth, q.y / depth);
        (w.l, w.r, w.b, w.t) = (w.l.min(x), w.r.max(x), w.b.min(y), w.t.max(y));
    }
    // A margin of a thousandth of the window (and never a window thinner than that) on each side:
    // receivers on the bounds' faces stay inside; the lookup clamps the rest to the edge texel.
    let m = 1e-3 * (w.r - w.l).max(w.t - w.b).max(1e-4);
    let w = Window {
        l: (w.l - m).max(-1.0),
        r: (w.r + m).min(1.0),
        b: (w.b - m).max(-1.0),
        t: (w.t + m).min(1.0),
    };
    if w.l >= w.r || w.b >= w.t {
        return FULL;
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(state: &mut u32) -> f32 {
        *state = state.wrapping_mul(1664525).wrapping_add(1013904223);
        (*state >> 8) as f32 / (1u32 << 24) as f32
    }

    /// Every point of the bounds whose direction from c falls on face f, and that the 90° face
    /// from y holds, lies in the window: checked on random points for lights above, beside and far
    /// from a box.
    #[test]
    fn the_window_holds_every_receiver_of_its_face() {
        let bounds = Bounds {
            min: Vec3::new(-15.0, 0.0, -20.0),
            max: Vec3::new(20.0, 3.0, 20.0),
        };
        let mut state = 11u32;
        for c in [
            Vec3::new(1.0, 6.0, 0.5),
            Vec3::new(1.0, 1000.0, 0.5),
            Vec3::new(40.0, 2.0, 3.0),
            Vec3::new(-30.0, 50.0, 60.0),
        ] {
            for face in 0..6 {
                let (forward, _, _) = face_axes(face);
                let up = if face / 2 == 1 { Vec3::Z } else { Vec3::Y };
                // y within the radius of c, as the ball's points are.
                let y = c + Vec3::new(0.7, -0.4, 0.3);
                let view = glam::camera::rh::view::look_to_mat4(y, forward, up);
                let w = fitted(c, face, &bounds, &view);
                for _ in 0..3000 {
                    let p = bounds.min
                        + (bounds.max - bounds.min)
                            * Vec3::new(lcg(&mut state), lcg(&mut state), lcg(&mut state));
                    if crate::scene::emitter::cube_face(p - c) != face {
                        continue;
                    }
                    let q = view.transform_point3(p);
                    let (x, yy) = (q.x / -q.z, q.y / -q.z);
                    if x.abs() > 1.0 || yy.abs() > 1.0 {
                        continue; // the edge texel's, as on the 90° face
                    }
                    assert!(
                        x >= w.l && x <= w.r && yy >= w.b && yy <= w.t,
                        "light {c}, face {face}: {p} at ({x}, {yy}) outside {w:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_far_light_fits_its_face_to_the_scene_and_a_light_inside_keeps_the_full_faces() {
        let bounds = Bounds {
            min: Vec3::new(-15.0, 0.0, -20.0),
            max: Vec3::new(20.0, 3.0, 20.0),
        };
        let c = Vec3::new(1.0, 1000.0, 0.5);
        let view = glam::camera::rh::view::look_to_mat4(c, Vec3::NEG_Y, Vec3::Z);
        let w = fitted(c, 3, &bounds, &view);
        // The scene is about 40 units across seen from 1000 up: a window about 0.04 wide.
        assert!(w.r - w.l < 0.05 && w.t - w.b < 0.05, "{w:?}");
        // The faces that serve nothing keep the full window.
        assert_eq!(fitted(c, 2, &bounds, &view), FULL);
        let inside = Vec3::new(0.0, 1.0, 0.0);
        assert_eq!(fitted(inside, 3, &bounds, &view), FULL);
    }
}
