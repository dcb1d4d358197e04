//! Closed forms for the `analytic-square` scene family (method.md §5), used to validate the tracer.
//!
//! Scene (y-up): ground plane `y = 0`; a square occluder of side `a` centred at `(ox, h_o, oz)`
//! and a square light of side `b` centred at `(lx, h_l, lz)`, both parallel to the ground, light
//! facing down (`edge_u = b·x̂`, `edge_v = b·ẑ`, so `n = -ŷ`), `h_l > h_o > 0`.
//!
//! Derivation. From `p` (below the occluder, `p.y < h_o`) the segment to a light point `y` crosses
//! the occluder plane at `q = p + (y - p)·λ`, `λ = (h_o - p.y)/(h_l - p.y) ∈ (0,1)`. So `y` is
//! blocked iff `q` lies in the occluder square, i.e. iff `y` lies in the central projection of the
//! occluder onto the light plane: `y = p + (q - p)·k`, `k = 1/λ = (h_l - p.y)/(h_o - p.y) > 1`.
//! That image is again an axis-aligned square, centre `p.xz + (o.xz - p.xz)·k`, side `k·a`.
//! Hence `V = 1 - overlap_x · overlap_z / b²` (product of 1-D interval overlaps), exactly.
//!
//! Boundary convention: a lattice point whose segment passes exactly through the occluder's edge
//! counts as blocked (the tracer's triangles are closed). Exact ties are ill-posed in f32, so tests
//! use [`analytic_lattice_margin`] to keep every lattice segment clear of the occluder's edges.

use super::sampling::{LATTICE_DIVISIONS, LATTICE_POINTS};
use super::RefLight;
use glam::{DVec3, Vec3};

/// One analytic-square configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnalyticSquareScene {
    pub light_center: Vec3,
    pub light_side: f32,
    pub occluder_center: Vec3,
    pub occluder_side: f32,
}

impl AnalyticSquareScene {
    /// The light as the tracer sees it (facing down).
    pub fn light(&self) -> RefLight {
        RefLight {
            center: self.light_center,
            edge_u: Vec3::X * self.light_side,
            edge_v: Vec3::Z * self.light_side,
        }
    }

    /// Ground quad `|x|,|z| <= ground_half_extent` at `y = 0` and the occluder, two triangles each.
    pub fn triangles(&self, ground_half_extent: f32) -> Vec<[Vec3; 3]> {
        let g = ground_half_extent;
        let mut tris = quad(Vec3::ZERO, g, g);
        let h = 0.5 * self.occluder_side;
        tris.extend(quad(self.occluder_center, h, h));
        tris
    }

    /// Exact `V(p)` for a point with normal `+y`. Points below the occluder plane see the
    /// projected square; points at or above it (but below the light) see the whole light.
    pub fn visibility(&self, p: Vec3) -> f32 {
        let (p, c, o) = (
            p.as_dvec3(),
            self.light_center.as_dvec3(),
            self.occluder_center.as_dvec3(),
        );
        let (a, b) = (self.occluder_side as f64, self.light_side as f64);
        if !positive(b) || p.y >= c.y {
            return 0.0; // no light, or p on or behind the light's plane
        }
        if !positive(a) || p.y >= o.y {
            return 1.0;
        }
        let k = (c.y - p.y) / (o.y - p.y);
        let half = 0.5 * a * k;
        let centre_x = p.x + (o.x - p.x) * k;
        let centre_z = p.z + (o.z - p.z) * k;
        let overlap = |proj: f64, light: f64| {
            ((proj + half).min(light + 0.5 * b) - (proj - half).max(light - 0.5 * b)).max(0.0)
        };
        let blocked = overlap(centre_x, c.x) * overlap(centre_z, c.z) / (b * b);
        (1.0 - blocked).clamp(0.0, 1.0) as f32
    }

    /// Fraction of the 289 lattice points whose segment to `p` misses the (closed) occluder.
    pub fn lattice_visibility(&self, p: Vec3) -> f32 {
        let (p, c) = (p.as_dvec3(), self.light_center.as_dvec3());
        if !positive(self.light_side as f64) || p.y >= c.y {
            return 0.0;
        }
        let Some((xs, zs)) = self.lattice_crossings(p) else {
            return 1.0;
        };
        let (o, half) = (
            self.occluder_center.as_dvec3(),
            0.5 * self.occluder_side as f64,
        );
        let inside =
            |qs: &[f64], centre: f64| qs.iter().filter(|&&q| (q - centre).abs() <= half).count();
        let blocked = inside(&xs, o.x) * inside(&zs, o.z);
        (LATTICE_POINTS - blocked) as f32 / LATTICE_POINTS as f32
    }

    /// Smallest distance, in the occluder plane, between a lattice segment's crossing coordinate
    /// and an occluder edge line; `f64::INFINITY` when the occluder is not between `p` and the light.
    /// Exact lattice comparisons need this well above f32 rounding (tests use 1e-3).
    pub fn lattice_margin(&self, p: Vec3) -> f64 {
        let Some((xs, zs)) = self.lattice_crossings(p.as_dvec3()) else {
            return f64::INFINITY;
        };
        let (o, half) = (
            self.occluder_center.as_dvec3(),
            0.5 * self.occluder_side as f64,
        );
        let gap = |qs: &[f64], centre: f64| {
            qs.iter()
                .map(|&q| ((q - centre).abs() - half).abs())
                .fold(f64::INFINITY, f64::min)
        };
        gap(&xs, o.x).min(gap(&zs, o.z))
    }

    /// Where the segments from `p` to the lattice columns (x) and rows (z) cross the occluder
    /// plane; the lattice is separable, so 17 + 17 values describe all 289 segments.
    fn lattice_crossings(&self, p: DVec3) -> Option<([f64; 17], [f64; 17])> {
        let (c, o) = (
            self.light_center.as_dvec3(),
            self.occluder_center.as_dvec3(),
        );
        if !positive(self.occluder_side as f64) || p.y >= o.y || p.y >= c.y {
            return None;
        }
        let lambda = (o.y - p.y) / (c.y - p.y);
        let b = self.light_side as f64;
        let mut xs = [0.0; 17];
        let mut zs = [0.0; 17];
        for i in 0..=LATTICE_DIVISIONS as usize {
            let s = i as f64 / LATTICE_DIVISIONS as f64 - 0.5;
            xs[i] = p.x + (c.x + s * b - p.x) * lambda;
            zs[i] = p.z + (c.z + s * b - p.z) * lambda;
        }
        Some((xs, zs))
    }
}

/// False for NaN too: a NaN size means no light / no occluder, never a NaN result.
fn positive(x: f64) -> bool {
    x > 0.0
}

/// Two triangles of the axis-aligned quad `centre ± (hx, 0, hz)` in a plane of constant y.
fn quad(centre: Vec3, hx: f32, hz: f32) -> Vec<[Vec3; 3]> {
    let c = |sx: f32, sz: f32| centre + Vec3::new(sx * hx, 0.0, sz * hz);
    let (a, b, d, e) = (c(-1.0, -1.0), c(1.0, -1.0), c(1.0, 1.0), c(-1.0, 1.0));
    vec![[a, b, d], [a, d, e]]
}

/// Closed-form `V(p)` for the analytic-square scene (see [`AnalyticSquareScene::visibility`]).
pub fn analytic_square_visibility(
    light_center: Vec3,
    light_side: f32,
    occluder_center: Vec3,
    occluder_side: f32,
    p: Vec3,
) -> f32 {
    AnalyticSquareScene {
        light_center,
        light_side,
        occluder_center,
        occluder_side,
    }
    .visibility(p)
}

/// Closed-form lattice `V(p)`: what the tracer's `Lattice` mode must return exactly.
pub fn analytic_lattice_visibility(
    light_center: Vec3,
    light_side: f32,
    occluder_center: Vec3,
    occluder_side: f32,
    p: Vec3,
) -> f32 {
    AnalyticSquareScene {
        light_center,
        light_side,
        occluder_center,
        occluder_side,
    }
    .lattice_visibility(p)
}

/// See [`AnalyticSquareScene::lattice_margin`].
pub fn analytic_lattice_margin(
    light_center: Vec3,
    light_side: f32,
    occluder_center: Vec3,
    occluder_side: f32,
    p: Vec3,
) -> f64 {
    AnalyticSquareScene {
        light_center,
        light_side,
        occluder_center,
        occluder_side,
    }
    .lattice_margin(p)
}
