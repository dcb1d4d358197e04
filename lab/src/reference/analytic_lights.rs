//! Closed forms for the light kinds' scenes (docs/lights.md §3), to validate the tracer as
//! `analytic.rs` does for the rectangle. Every emitter is a disk sampled uniformly by area
//! (`emitter.rs`); a straight occluder edge cuts that disk along a line, so V is one minus the
//! share of a unit disk beyond a line at signed distance δ from its centre:
//! `S(δ) = (acos δ − δ·√(1 − δ²)) / π` for `|δ| ≤ 1` (1 below, 0 above).

use glam::DVec3;
use std::f64::consts::PI;

/// Share of the unit disk where `q·n > δ` for a unit `n`: a circular segment over the disk's area.
pub fn segment_share(delta: f64) -> f64 {
    let d = delta.clamp(-1.0, 1.0);
    (d.acos() - d * (1.0 - d * d).sqrt()) / PI
}

/// A disk light facing down (centre `light_center`, `radius`) over a horizontal bar `x ∈ [x0, x1]`
/// at `height`, long in z. From `p` below the bar, the central projection onto the light's plane
/// scales by `k = (h_l − p.y)/(h − p.y)` about `p`: the bar's image is the strip
/// `[p.x + (x0 − p.x)·k, p.x + (x1 − p.x)·k]`, and the blocked share of the disk is
/// `S(lo') − S(hi')` with lo', hi' the strip's sides measured from the disk's centre in radii.
#[derive(Clone, Copy, Debug)]
pub struct DiskOverBar {
    pub light_center: DVec3,
    pub radius: f64,
    pub x0: f64,
    pub x1: f64,
    pub height: f64,
}

impl DiskOverBar {
    pub fn visibility(&self, p: DVec3) -> f64 {
        let c = self.light_center;
        if p.y >= c.y {
            return 0.0; // on or behind the light's plane
        }
        if p.y >= self.height {
            return 1.0;
        }
        let k = (c.y - p.y) / (self.height - p.y);
        let side = |x: f64| (p.x + (x - p.x) * k - c.x) / self.radius;
        1.0 - (segment_share(side(self.x0)) - segment_share(side(self.x1)))
    }
}

/// Blocked share of a disk of directions `ω ∝ axis + spread·q` (`q` uniform in the unit disk
/// across the unit `axis`) by the half-plane `y = height, x > edge_x`, seen from `p` below it.
///
/// The ray along ω crosses `y = height` at `x = p.x + ω.x·(h − p.y)/ω.y`, beyond the edge iff
/// `g·ω > 0` with `g = (h − p.y, −(edge_x − p.x), 0)` (for ω.y > 0). With `g⊥` the part of g
/// across the axis, that is `q·ĝ⊥ > δ = −(g·axis)/(spread·|g⊥|)`: a segment, `S(δ)`.
pub fn half_plane_share(p: DVec3, axis: DVec3, spread: f64, height: f64, edge_x: f64) -> f64 {
    if p.y >= height {
        return 0.0;
    }
    let g = DVec3::new(height - p.y, -(edge_x - p.x), 0.0);
    let along = g.dot(axis);
    let across = (g - axis * along).length();
    if across == 0.0 {
        return if along > 0.0 { 1.0 } else { 0.0 };
    }
    segment_share(-along / (spread * across))
}

/// The sun (unit `toward` it, `tan_half` of its angular radius) over the half-plane
/// `y = height, x > edge_x`.
#[derive(Clone, Copy, Debug)]
pub struct SunOverEdge {
    pub toward: DVec3,
    pub tan_half: f64,
    pub height: f64,
    pub edge_x: f64,
}

impl SunOverEdge {
    pub fn visibility(&self, p: DVec3) -> f64 {
        1.0 - half_plane_share(p, self.toward, self.tan_half, self.height, self.edge_x)
    }
}

/// An emitter sphere (a point or spot light) above the half-plane `y = height, x > edge_x`, its
/// lowest point above the plane. Seen from `p` at distance d it is the disk of directions around
/// `(c − p)/d` with `spread = r/√(d² − r²)` (the tangent cone).
#[derive(Clone, Copy, Debug)]
pub struct SphereOverEdge {
    pub center: DVec3,
    pub radius: f64,
    pub height: f64,
    pub edge_x: f64,
}

impl SphereOverEdge {
    pub fn visibility(&self, p: DVec3) -> f64 {
        let to_c = self.center - p;
        let d2 = to_c.length_squared();
        let r2 = self.radius * self.radius;
        if d2 <= r2 {
            return 0.0;
        }
        let spread = self.radius / (d2 - r2).sqrt();
        1.0 - half_plane_share(p, to_c / d2.sqrt(), spread, self.height, self.edge_x)
    }
}

/// On the axis of a sphere (radius r, distance d) behind a coaxial disk occluder (radius a,
/// distance h from `p`, between p and the sphere): the occluder is the disk of directions of
/// radius `a/h`, the sphere's of radius `r/√(d² − r²)`, so `V = 1 − min(1, (a/h)² (d² − r²)/r²)`.
pub fn sphere_behind_disk_on_axis(d: f64, r: f64, h: f64, a: f64) -> f64 {
    1.0 - ((a / h).powi(2) * (d * d - r * r) / (r * r)).min(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_segment_share_runs_from_one_to_zero_through_a_half() {
        assert_eq!(segment_share(-1.5), 1.0);
        assert_eq!(segment_share(1.0), 0.0);
        assert!((segment_share(0.0) - 0.5).abs() < 1e-15);
        // Symmetric: S(δ) + S(−δ) = 1.
        for d in [0.1, 0.37, 0.8] {
            assert!((segment_share(d) + segment_share(-d) - 1.0).abs() < 1e-12);
        }
        // Against a fine count over the disk.
        let (n, delta) = (2000, 0.3);
        let (mut inside, mut beyond) = (0u64, 0u64);
        for j in 0..n {
            for i in 0..n {
                let (x, y) = (
                    (i as f64 + 0.5) / n as f64 * 2.0 - 1.0,
                    (j as f64 + 0.5) / n as f64 * 2.0 - 1.0,
                );
                if x * x + y * y <= 1.0 {
                    inside += 1;
                    beyond += (x > delta) as u64;
                }
            }
        }
        assert!((beyond as f64 / inside as f64 - segment_share(delta)).abs() < 1e-4);
    }

    #[test]
    fn under_the_edge_half_the_sun_is_hidden() {
        let sun = SunOverEdge {
            toward: DVec3::Y,
            tan_half: 0.1,
            height: 2.0,
            edge_x: 0.0,
        };
        assert!((sun.visibility(DVec3::ZERO) - 0.5).abs() < 1e-12);
        assert_eq!(sun.visibility(DVec3::new(-1.0, 0.0, 0.0)), 1.0);
        assert_eq!(sun.visibility(DVec3::new(1.0, 0.0, 0.0)), 0.0);
    }
}
