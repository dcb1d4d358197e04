//! Where the cascades go: the camera's depth range cut into slices (uniform, logarithmic or the
//! practical blend of the two), and each slice's bounding sphere, which its map is fitted to.
//! CPU only, before the frame: the slices follow the camera and the scene's bounds.

use crate::scene::light::Bounds;
use crate::scene::Camera;
use glam::Vec3;

/// How the depth range is cut (docs/lights.md "Cascades").
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Scheme {
    /// Equal slices: z_i = n + (f − n)·i/N.
    Uniform,
    /// Equal ratios: z_i = n·(f/n)^(i/N), the texel density a perspective view asks for.
    Log,
    /// λ·log + (1 − λ)·uniform (Zhang et al.'s practical split).
    Practical,
}

impl Scheme {
    pub const ALL: [Scheme; 3] = [Scheme::Uniform, Scheme::Log, Scheme::Practical];
    pub(crate) const NAMES: [&'static str; 3] = ["uniform", "log", "practical"];

    pub fn name(self) -> &'static str {
        Self::NAMES[Self::ALL.iter().position(|s| *s == self).unwrap_or(0)]
    }
    pub fn parse(s: &str) -> Option<Scheme> {
        Self::NAMES
            .iter()
            .position(|n| *n == s)
            .map(|i| Self::ALL[i])
    }
}

/// The nearest view depth a slice starts at, as a share of the far end, when the scene's bounds
/// reach behind the camera (a camera standing on the ground): a log split needs a near plane > 0.
pub(crate) const NEAR_SHARE: f32 = 1.0 / 256.0;

/// The camera's unit forward.
pub fn forward(camera: &Camera) -> Vec3 {
    (camera.target - camera.eye).normalize()
}

/// The depth range the cascades cover: from the nearest to the farthest corner of the bounds
/// along the view, the near end at least `NEAR_SHARE` of the far one.
pub(crate) fn depth_range(camera: &Camera, bounds: &Bounds) -> (f32, f32) {
    let f = forward(camera);
    let depths = bounds.corners().map(|c| (c - camera.eye).dot(f));
    let far = depths
        .iter()
        .copied()
        .fold(f32::NEG_INFINITY, f32::max)
        .max(1e-3);
    let near = depths
        .iter()
        .copied()
        .fold(f32::INFINITY, f32::min)
        .max(far * NEAR_SHARE);
    (near, far)
}

/// The N + 1 slice ends z_0 = near … z_N = far of `scheme` (`lambda` weights log in `practical`).
pub(crate) fn split_depths(scheme: Scheme, lambda: f32, n: u32, near: f32, far: f32) -> Vec<f32> {
    let lambda = match scheme {
        Scheme::Uniform => 0.0,
        Scheme::Log => 1.0,
        Scheme::Practical => lambda,
    };
    (0..=n)
        .map(|i| {
            if i == n {
                return far; // exact, so the last slice ends at the range's end
            }
            let t = i as f32 / n as f32;
            lambda * near * (far / near).powf(t) + (1.0 - lambda) * (near + (far - near) * t)
        })
        .collect()
}

/// The sphere around the view frustum's slice between depths z0 and z1: centred on the view axis
/// at the mean depth, through the farthest of the slice's eight corners. Its radius depends on the
/// slice alone, so turning the camera moves the sphere without resizing it (its map's texels keep
/// their size: rotation-stable).
pub(crate) fn slice_sphere(camera: &Camera, aspect: f32, z0: f32, z1: f32) -> (Vec3, f32) {
    let tan_y = (0.5 * camera.fov_y_deg.to_radians()).tan();
    // A corner at depth z lies z·k off the axis.
    let k = tan_y * (1.0 + aspect * aspect).sqrt();
    let mid = 0.5 * (z0 + z1);
    let radius = [z0, z1]
        .iter()
        .map(|&z| ((z - mid).powi(2) + (z * k).powi(2)).sqrt())
        .fold(0.0, f32::max);
    (camera.eye + forward(camera) * mid, radius)
}

/// `radius` rounded up to 5 significant bits (steps of 1/16 to 1/32 of it). The slice ends move
/// with the camera (the depth range follows the bounds), so the exact sphere would change its
/// texel size, and with it every texel edge, at each step; rounded, a map keeps its texel through
/// most moves and snapping keeps the edges in place.
pub(crate) fn quantize(radius: f32) -> f32 {
    let step = 2f32.powi(radius.max(1e-6).log2().floor() as i32 - 4);
    (radius / step).ceil() * step
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantized_radii_hold_the_sphere_and_stay_put_under_small_changes() {
        for r in [0.3f32, 1.0, 7.7, 45.2, 180.0] {
            let q = quantize(r);
            assert!(q >= r && q < r * (1.0 + 1.0 / 16.0) + 1e-6, "{r} -> {q}");
        }
        assert_eq!(quantize(45.2), quantize(45.3));
    }

    #[test]
    fn the_schemes_follow_their_formulas() {
        let (n, f) = (1.0f32, 256.0f32);
        let u = split_depths(Scheme::Uniform, 0.5, 4, n, f);
        let l = split_depths(Scheme::Log, 0.5, 4, n, f);
        let p = split_depths(Scheme::Practical, 0.5, 4, n, f);
        assert_eq!(u, vec![1.0, 64.75, 128.5, 192.25, 256.0]);
        for (i, want) in [1.0f32, 4.0, 16.0, 64.0, 256.0].iter().enumerate() {
            assert!(
                (l[i] - want).abs() < 1e-3 * want,
                "log {i}: {} against {want}",
                l[i]
            );
            assert!(
                (p[i] - 0.5 * (l[i] + u[i])).abs() < 1e-3 * want.max(1.0),
                "practical {i}"
            );
        }
        // One cascade covers the whole range under every scheme.
        for s in Scheme::ALL {
            assert_eq!(split_depths(s, 0.5, 1, n, f), vec![n, f]);
        }
    }

    #[test]
    fn the_sphere_holds_the_slice_and_keeps_its_radius_when_the_camera_turns() {
        let a = Camera {
            eye: Vec3::new(1.0, 2.0, 3.0),
            target: Vec3::new(1.0, 2.0, -10.0),
            up: Vec3::Y,
            fov_y_deg: 50.0,
        };
        let b = Camera {
            target: Vec3::new(8.0, 0.0, 1.0),
            ..a
        };
        let (ca, ra) = slice_sphere(&a, 1.5, 4.0, 20.0);
        let (cb, rb) = slice_sphere(&b, 1.5, 4.0, 20.0);
        assert_eq!(ra, rb);
        assert!(((ca - a.eye).length() - (cb - b.eye).length()).abs() < 1e-4);
        // Every corner of the slice lies inside.
        let tan_y = 25f32.to_radians().tan();
        for z in [4.0f32, 20.0] {
            for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
                let corner = a.eye + Vec3::new(sx * z * tan_y * 1.5, sy * z * tan_y, -z);
                assert!(
                    (corner - ca).length() <= ra * (1.0 + 1e-5),
                    "corner at depth {z} outside"
                );
            }
        }
    }
}
