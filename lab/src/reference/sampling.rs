//! Light sample positions: the 17×17 lattice and per-pixel stratified jitter.

use super::{RefLight, ReferenceMode};
use glam::Vec3;

/// `L_max = 4` (method.md §3): lattice coordinates are `i / 16`, `i ∈ 0..=16`.
pub const LATTICE_DIVISIONS: u32 = 16;
/// Points per lattice side.
pub const LATTICE_SIDE: usize = LATTICE_DIVISIONS as usize + 1;
/// `(2^L_max + 1)² = 289`.
pub const LATTICE_POINTS: usize = LATTICE_SIDE * LATTICE_SIDE;

/// Lattice coordinate `i / 16` (exact in f32).
#[inline]
pub fn lattice_coord(i: u32) -> f32 {
    i as f32 / LATTICE_DIVISIONS as f32
}

/// SplitMix64 finaliser: a cheap, well-mixed 64-bit bijection.
#[inline]
pub fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Deterministic per-pixel random stream (SplitMix64 sequence seeded from `(seed, pixel)`).
pub struct PixelRng(u64);

impl PixelRng {
    /// Hashing both inputs decorrelates neighbouring pixels and different seeds.
    pub fn new(seed: u64, pixel: u64) -> PixelRng {
        PixelRng(splitmix64(seed ^ splitmix64(pixel)))
    }

    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        splitmix64(self.0)
    }

    /// Uniform in `[0, 1)`: the top 24 bits, so every value is exact in f32 and 1.0 never occurs.
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }
}

/// Calls `f(s, t)` for each unit-square point of `mode` for pixel `pixel`, in a fixed order with
/// the pixel's own seed: what every emitter's reference samples start from.
/// `Continuous { m: 0 }` yields no points; callers reject it before tracing.
pub fn for_each_unit_sample(mode: &ReferenceMode, pixel: u64, mut f: impl FnMut(f32, f32)) {
    match *mode {
        ReferenceMode::Lattice => {
            for j in 0..=LATTICE_DIVISIONS {
                for i in 0..=LATTICE_DIVISIONS {
                    f(lattice_coord(i), lattice_coord(j));
                }
            }
        }
        ReferenceMode::Point { s, t } => f(s, t),
        ReferenceMode::Continuous { m, seed } => {
            let mut rng = PixelRng::new(seed, pixel);
            let inv_m = 1.0 / m as f32;
            for b in 0..m {
                for a in 0..m {
                    let s = (a as f32 + rng.next_f32()) * inv_m;
                    let t = (b as f32 + rng.next_f32()) * inv_m;
                    f(s, t);
                }
            }
        }
    }
}

/// Fills `out` with the light points of `mode` for pixel `pixel` (cleared first).
pub fn fill_light_samples(mode: &ReferenceMode, light: &RefLight, pixel: u64, out: &mut Vec<Vec3>) {
    out.clear();
    for_each_unit_sample(mode, pixel, |s, t| out.push(light.point(s, t)));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_light() -> RefLight {
        RefLight {
            center: Vec3::ZERO,
            edge_u: Vec3::X,
            edge_v: Vec3::Z,
        }
    }

    #[test]
    fn lattice_has_289_points_on_the_light_corners_included() {
        let mut out = Vec::new();
        fill_light_samples(&ReferenceMode::Lattice, &unit_light(), 0, &mut out);
        assert_eq!(out.len(), 289);
        assert_eq!(out[0], Vec3::new(-0.5, 0.0, -0.5));
        assert_eq!(out[288], Vec3::new(0.5, 0.0, 0.5));
        assert_eq!(out[8 * 17 + 8], Vec3::ZERO);
    }

    #[test]
    fn continuous_is_stratified_deterministic_and_decorrelated_per_pixel() {
        let mode = ReferenceMode::Continuous { m: 8, seed: 7 };
        let (mut a, mut b, mut c) = (Vec::new(), Vec::new(), Vec::new());
        fill_light_samples(&mode, &unit_light(), 3, &mut a);
        fill_light_samples(&mode, &unit_light(), 3, &mut b);
        fill_light_samples(&mode, &unit_light(), 4, &mut c);
        assert_eq!(a, b);
        assert_ne!(a, c);
        for (k, p) in a.iter().enumerate() {
            let (ia, ib) = ((k % 8) as f32, (k / 8) as f32);
            let (s, t) = (p.x + 0.5, p.z + 0.5);
            assert!(
                s >= ia / 8.0 && s <= (ia + 1.0) / 8.0,
                "sample {k} outside its stratum"
            );
            assert!(
                t >= ib / 8.0 && t <= (ib + 1.0) / 8.0,
                "sample {k} outside its stratum"
            );
        }
    }
}
