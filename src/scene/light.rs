//! The rectangular area light and the view of one light sample (method.md §1-2).

use crate::gpu::structs::GpuSample;
use glam::{Mat4, Vec3, Vec4};

/// `y(s,t) = center + (s-½)·edge_u + (t-½)·edge_v`, emitting on the side of `normalize(edge_u × edge_v)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaLight {
    pub center: Vec3,
    pub edge_u: Vec3,
    pub edge_v: Vec3,
}

impl AreaLight {
    pub fn point(&self, s: f32, t: f32) -> Vec3 {
        self.center + (s - 0.5) * self.edge_u + (t - 0.5) * self.edge_v
    }
    pub fn normal(&self) -> Vec3 {
        self.edge_u.cross(self.edge_v).normalize()
    }
    pub fn area(&self) -> f32 {
        self.edge_u.cross(self.edge_v).length()
    }
}

// The scene's bounds live beside the light that fits its frusta to them; `cube_window` reads them
// too, so they sit in a file of their own.
pub use super::bounds::Bounds;

/// Widest field of view a sample's frustum may take (tan of the half-angle): beyond it the map's
/// texels grow too large to be useful; geometry outside counts as unoccluding.
pub(crate) const MAX_TAN_HALF: f32 = 6.0;

/// Where `p` lies in the view of a map from light point `y` (the frame `sample_view` builds):
/// its tangents across the two axes, or None where it lies at or behind `y`'s plane.
pub(crate) fn tangents_seen(light: &AreaLight, y: Vec3, p: Vec3) -> Option<(f32, f32)> {
    let forward = light.normal();
    let right = (light.edge_u - forward * light.edge_u.dot(forward)).normalize();
    let up = forward.cross(right).normalize() * -1.0;
    let d = p - y;
    let depth = d.dot(forward);
    (depth > 0.0).then(|| (d.dot(right) / depth, d.dot(up) / depth))
}

/// Perspective view from light point `y` looking along the light's normal, with an off-axis frustum
/// fitted to the scene bounds (so every sample's map covers the scene with the same axes).
pub fn sample_view(
    light: &AreaLight,
    y: Vec3,
    bounds: &Bounds,
    map_size: u32,
    lattice: u32,
) -> GpuSample {
    sample_view_window(light, y, bounds, bounds, map_size, lattice)
}

/// `sample_view` whose frustum's sides are fitted to `window` (the receivers a map serves, inside
/// `bounds`), its depth range still to `bounds`: every occluder between the light point and a
/// receiver in the window projects into the window, so the map's texels go to those receivers
/// alone. With `window = bounds` it is `sample_view`, bit for bit.
pub(crate) fn sample_view_window(
    light: &AreaLight,
    y: Vec3,
    bounds: &Bounds,
    window: &Bounds,
    map_size: u32,
    lattice: u32,
) -> GpuSample {
    let forward = light.normal();
    let right = (light.edge_u - forward * light.edge_u.dot(forward)).normalize();
    let up = forward.cross(right).normalize() * -1.0;
    // view space: x = right, y = up, looking down -z (right-handed, as glam's look_to_rh).
    let view = glam::camera::rh::view::look_to_mat4(y, forward, up);
    let diag = bounds.diagonal().max(1e-6);
    let mut far: f32 = 0.0;
    let mut near = f32::INFINITY;
    let (mut l, mut r, mut b, mut t) = (
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::INFINITY,
        f32::NEG_INFINITY,
    );
    for c in bounds.corners() {
        let depth = -view.transform_point3(c).z;
        far = far.max(depth);
        near = near.min(depth);
    }
    for c in window.corners() {
        let v = view.transform_point3(c);
        let d = (-v.z).max(diag * 1e-3);
        l = l.min(v.x / d);
        r = r.max(v.x / d);
        b = b.min(v.y / d);
        t = t.max(v.y / d);
    }
    far = far.max(diag * 1e-2) * 1.01;
    // Margin so geometry at the bounds' nearest corner is not clipped; geometry at the light's plane
    // would need near = 0, so keep depth precision and clip that sliver.
    let near = (near * 0.95).max(far * 1e-3);
    let clamp = |x: f32| x.clamp(-MAX_TAN_HALF, MAX_TAN_HALF);
    let (l, r, b, t) = (
        clamp(l) * 1.001,
        clamp(r) * 1.001,
        clamp(b) * 1.001,
        clamp(t) * 1.001,
    );
    let proj = off_axis_perspective(l * near, r * near, b * near, t * near, near, far);
    let texel_angle = (r - l).max(t - b) / map_size as f32;
    let rr = far / (near - far);
    GpuSample {
        light_from_world: (proj * view).to_cols_array_2d(),
        position: Vec4::from((y, 1.0)).to_array(),
        texel_angle,
        depth_lin_a: rr * near,
        depth_lin_b: rr,
        layer: 0,
        array: 0,
        lattice,
        orthographic: 0,
        cube_face: 0,
    }
}

/// Face `face` (0..5: +x, −x, +y, −y, +z, −z) of the cube map from light point `y` of the sphere
/// centred at `centre`: a perspective frustum along the face's axis whose window holds the part of
/// the bounds the face serves (the receivers whose direction from `centre` has that axis dominant,
/// `cube_window::fitted`), or the symmetric 90° face where no fit applies. Far reaches the bounds'
/// farthest corner, near the bounds' nearest point (for depth precision), and `cube_face` is
/// `face + 1` (the lookup's face test).
pub(crate) fn cube_face_view(
    centre: Vec3,
    y: Vec3,
    face: u32,
    bounds: &Bounds,
    map_size: u32,
    lattice: u32,
) -> GpuSample {
    let axis = [Vec3::X, Vec3::Y, Vec3::Z][(face / 2) as usize];
    let forward = if face % 2 == 0 { axis } else { -axis };
    let up = if face / 2 == 1 { Vec3::Z } else { Vec3::Y };
    let view = glam::camera::rh::view::look_to_mat4(y, forward, up);
    let diag = bounds.diagonal().max(1e-6);
    let far = bounds
        .corners()
        .iter()
        .map(|c| (*c - y).length())
        .fold(0.0f32, f32::max)
        .max(diag * 1e-2)
        * 1.01;
    let nearest = (y.clamp(bounds.min, bounds.max) - y).length();
    let near = (nearest * 0.95).max(far * 1e-3);
    let w = super::cube_window::fitted(centre, face, bounds, &view);
    let proj = off_axis_perspective(w.l * near, w.r * near, w.b * near, w.t * near, near, far);
    let rr = far / (near - far);
    GpuSample {
        light_from_world: (proj * view).to_cols_array_2d(),
        position: Vec4::from((y, 1.0)).to_array(),
        texel_angle: (w.r - w.l).max(w.t - w.b) / map_size as f32,
        depth_lin_a: rr * near,
        depth_lin_b: rr,
        layer: 0,
        array: 0,
        lattice,
        orthographic: 0,
        cube_face: face + 1,
    }
}

/// Orthographic view along `-toward` (a light at infinity, the sun's), its box fitted to the scene
/// bounds, x along `right_hint` across the view. Depth is linear: `depth_lin_a·d + depth_lin_b`;
/// `texel_angle` is the texel's world size (clip.w is 1, so the lookup's `depth·texel_angle` is
/// that size at every depth: bias in texels is a fixed world distance); `position` is `toward`
/// with w = 0, the direction the lookup's facing test and slope read.
pub(crate) fn orthographic_view(
    toward: Vec3,
    right_hint: Vec3,
    bounds: &Bounds,
    map_size: u32,
    lattice: u32,
) -> GpuSample {
    let forward = -toward;
    let right = (right_hint - forward * right_hint.dot(forward)).normalize();
    let up = forward.cross(right).normalize() * -1.0;
    let diag = bounds.diagonal().max(1e-6);
    let eye = bounds.min.lerp(bounds.max, 0.5) + toward * diag;
    let view = glam::camera::rh::view::look_to_mat4(eye, forward, up);
    let (mut l, mut r, mut b, mut t) = (
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::INFINITY,
        f32::NEG_INFINITY,
    );
    let (mut near, mut far) = (f32::INFINITY, f32::NEG_INFINITY);
    for c in bounds.corners() {
        let v = view.transform_point3(c);
        (l, r, b, t) = (l.min(v.x), r.max(v.x), b.min(v.y), t.max(v.y));
        (near, far) = (near.min(-v.z), far.max(-v.z));
    }
    // The same margins as the perspective fit: nothing at the bounds is clipped.
    let m = 1e-3 * diag;
    let (l, r, b, t) = (l - m, r + m, b - m, t + m);
    let (near, far) = (near - 1e-2 * diag, far + 1e-2 * diag);
    let proj = off_axis_orthographic(l, r, b, t, near, far);
    GpuSample {
        light_from_world: (proj * view).to_cols_array_2d(),
        position: Vec4::from((toward, 0.0)).to_array(),
        texel_angle: (r - l).max(t - b) / map_size as f32,
        depth_lin_a: far - near,
        depth_lin_b: near,
        layer: 0,
        array: 0,
        lattice,
        orthographic: 1,
        cube_face: 0,
    }
}

/// Orthographic view along `-toward` over a square of half-side `half` around `centre` (a cascade,
/// docs/lights.md "Cascades"), with the axes and the depth range of [`orthographic_view`] over the
/// same bounds. The light-space frame is fixed by the bounds alone, and the square's centre is
/// moved to a whole number of texels in it, so every texel edge keeps its world place while the
/// square follows the camera: the map does not shimmer.
pub(crate) fn orthographic_square(
    toward: Vec3,
    right_hint: Vec3,
    bounds: &Bounds,
    centre: Vec3,
    half: f32,
    map_size: u32,
    layer: u32,
) -> GpuSample {
    let forward = -toward;
    let right = (right_hint - forward * right_hint.dot(forward)).normalize();
    let up = forward.cross(right).normalize() * -1.0;
    let diag = bounds.diagonal().max(1e-6);
    let eye = bounds.min.lerp(bounds.max, 0.5) + toward * diag;
    let view = glam::camera::rh::view::look_to_mat4(eye, forward, up);
    let (mut near, mut far) = (f32::INFINITY, f32::NEG_INFINITY);
    for c in bounds.corners() {
        let v = view.transform_point3(c);
        (near, far) = (near.min(-v.z), far.max(-v.z));
    }
    let (near, far) = (near - 1e-2 * diag, far + 1e-2 * diag);
    let texel = 2.0 * half / map_size as f32;
    let c = view.transform_point3(centre);
    let (x, y) = ((c.x / texel).round() * texel, (c.y / texel).round() * texel);
    let proj = off_axis_orthographic(x - half, x + half, y - half, y + half, near, far);
    GpuSample {
        light_from_world: (proj * view).to_cols_array_2d(),
        position: Vec4::from((toward, 0.0)).to_array(),
        texel_angle: texel,
        depth_lin_a: far - near,
        depth_lin_b: near,
        layer,
        array: 0,
        lattice: u32::MAX,
        orthographic: 1,
        cube_face: 0,
    }
}

/// Right-handed orthographic box with depth in [0, 1] (wgpu): d = (depth − near) / (far − near).
fn off_axis_orthographic(
    left: f32,
    right: f32,
    bottom: f32,
    top: f32,
    near: f32,
    far: f32,
) -> Mat4 {
    let rr = 1.0 / (near - far);
    Mat4::from_cols(
        Vec4::new(2.0 / (right - left), 0.0, 0.0, 0.0),
        Vec4::new(0.0, 2.0 / (top - bottom), 0.0, 0.0),
        Vec4::new(0.0, 0.0, rr, 0.0),
        Vec4::new(
            -(right + left) / (right - left),
            -(top + bottom) / (top - bottom),
            rr * near,
            1.0,
        ),
    )
}

/// Right-handed off-axis perspective with depth in [0, 1] (wgpu), like glam's `perspective_rh`.
fn off_axis_perspective(left: f32, right: f32, bottom: f32, top: f32, near: f32, far: f32) -> Mat4 {
    let rr = far / (near - far);
    Mat4::from_cols(
        Vec4::new(2.0 * near / (right - left), 0.0, 0.0, 0.0),
        Vec4::new(0.0, 2.0 * near / (top - bottom), 0.0, 0.0),
        Vec4::new(
            (right + left) / (right - left),
            (top + bottom) / (top - bottom),
            rr,
            -1.0,
        ),
        Vec4::new(0.0, 0.0, rr * near, 0.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frustum_contains_the_bounds_and_depth_linearises() {
        let light = AreaLight {
            center: Vec3::new(0.0, 10.0, 0.0),
            edge_u: Vec3::X * 2.0,
            edge_v: Vec3::Z * 2.0,
        };
        assert!((light.normal() - Vec3::NEG_Y).length() < 1e-6);
        let bounds = Bounds {
            min: Vec3::new(-5.0, 0.0, -5.0),
            max: Vec3::new(5.0, 3.0, 5.0),
        };
        let s = sample_view(&light, light.point(0.0, 1.0), &bounds, 256, 0);
        let m = Mat4::from_cols_array_2d(&s.light_from_world);
        for c in bounds.corners() {
            let clip = m * Vec4::from((c, 1.0));
            let ndc = clip.truncate() / clip.w;
            assert!(
                ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 && (0.0..=1.0).contains(&ndc.z),
                "{c} -> {ndc}"
            );
            let lin = s.depth_lin_a / (ndc.z + s.depth_lin_b);
            assert!(
                (lin - clip.w).abs() < 1e-3 * clip.w,
                "linear depth {lin} vs {}",
                clip.w
            );
        }
    }

    #[test]
    fn each_cube_face_holds_the_directions_its_axis_dominates() {
        let bounds = Bounds {
            min: Vec3::new(-5.0, 0.0, -5.0),
            max: Vec3::new(5.0, 3.0, 5.0),
        };
        let y = Vec3::new(0.5, 2.0, -1.0);
        let faces: Vec<GpuSample> = (0..6)
            .map(|f| cube_face_view(y, y, f, &bounds, 256, 0))
            .collect();
        let mut state = 7u32;
        for _ in 0..2000 {
            let mut r = || {
                state = state.wrapping_mul(1664525).wrapping_add(1013904223);
                (state >> 8) as f32 / (1u32 << 24) as f32
            };
            let p = bounds.min + (bounds.max - bounds.min) * Vec3::new(r(), r(), r());
            let d = p - y;
            let axis = if d.x.abs() >= d.y.abs() && d.x.abs() >= d.z.abs() {
                0
            } else if d.y.abs() >= d.z.abs() {
                1
            } else {
                2
            };
            let f = axis * 2 + (d[axis] < 0.0) as usize;
            let clip = Mat4::from_cols_array_2d(&faces[f].light_from_world) * Vec4::from((p, 1.0));
            let ndc = clip.truncate() / clip.w;
            assert!(
                clip.w > 0.0
                    && ndc.x.abs() <= 1.0 + 1e-5
                    && ndc.y.abs() <= 1.0 + 1e-5
                    && (0.0..=1.0).contains(&ndc.z),
                "{p} on face {f}: {ndc}"
            );
            // clip.w is the depth along the face's axis, which the linear-depth constants recover.
            let lin = faces[f].depth_lin_a / (ndc.z + faces[f].depth_lin_b);
            assert!(
                (lin - clip.w).abs() < 1e-3 * clip.w,
                "linear depth {lin} vs {}",
                clip.w
            );
        }
    }

    #[test]
    fn orthographic_box_contains_the_bounds_and_depth_is_linear() {
        let bounds = Bounds {
            min: Vec3::new(-5.0, 0.0, -5.0),
            max: Vec3::new(5.0, 3.0, 5.0),
        };
        let toward = Vec3::new(0.3, 1.0, -0.2).normalize();
        let s = orthographic_view(toward, Vec3::X, &bounds, 256, 0);
        let m = Mat4::from_cols_array_2d(&s.light_from_world);
        let eye = Vec3::new(0.0, 1.5, 0.0) + toward * bounds.diagonal();
        for c in bounds.corners() {
            let clip = m * Vec4::from((c, 1.0));
            assert_eq!(clip.w, 1.0);
            assert!(
                clip.x.abs() <= 1.0 && clip.y.abs() <= 1.0 && (0.0..=1.0).contains(&clip.z),
                "{c} -> {clip}"
            );
            let lin = s.depth_lin_a * clip.z + s.depth_lin_b;
            let depth = (c - eye).dot(-toward);
            assert!(
                (lin - depth).abs() < 1e-4 * bounds.diagonal(),
                "linear depth {lin} vs {depth}"
            );
        }
        // A texel's world size: the box's wider side over the map.
        let a = m * Vec4::new(0.0, 0.0, 0.0, 1.0);
        let across = (Vec3::X - toward * toward.x).normalize();
        let b = m * Vec4::from((across * s.texel_angle, 1.0));
        // One texel_angle across is at most one texel (the wider side sets it), and here, with a
        // near-square footprint, close to one.
        let texels = (b.x - a.x).abs() * 0.5 * 256.0;
        assert!(texels <= 1.0 + 1e-3 && texels > 0.8, "{texels} texels");
    }
}
