//! Sample weights for scope = global: the seed's level rule, or leaf-quad areas.

use super::levels::LevelReport;
use crate::methods::adaptive::buffers::{LATTICE_POINTS, NO_SPLIT};
use crate::methods::{AdaptiveParams, Weights};

/// ŵ_k for every lattice index (0 where no map was rendered); Σ ŵ = 1.
pub fn sample_weights(
    p: &AdaptiveParams,
    levels: &[LevelReport],
    sample_level: &[u32],
    rendered: &[u32],
) -> Vec<f32> {
    if p.border_strip() == 0.0 {
        // The corner-to-corner lattice: exact integers, normalised as kernels/weights.wgsl does.
        let n = lattice_numerators(p, levels, sample_level, rendered);
        let total: i64 = n.iter().sum();
        return n.iter().map(|&x| ratio_f32(x, total)).collect();
    }
    let mut w = vec![0f64; LATTICE_POINTS as usize];
    match p.weights {
        Weights::Level => {
            for &k in rendered {
                let l = sample_level[k as usize];
                let d = (1u64 << l) as f64 + 1.0;
                w[k as usize] = 1.0 / (d * d);
            }
        }
        Weights::Area => {
            for r in levels {
                for (q, quad) in r.quads.iter().enumerate() {
                    let leaf = r.split_base.get(q).is_none_or(|&s| s == NO_SPLIT);
                    if leaf {
                        let area = (quad.size as f64 / 16.0).powi(2);
                        for c in 0..4 {
                            let i = quad.i + (c & 1) * quad.size;
                            let j = quad.j + (c >> 1) * quad.size;
                            w[(j * 17 + i) as usize] += area / 4.0;
                        }
                    }
                }
            }
        }
        Weights::Coons => {
            let mut have = vec![false; LATTICE_POINTS as usize];
            for &k in rendered {
                have[k as usize] = true;
            }
            for r in levels {
                for (q, quad) in r.quads.iter().enumerate() {
                    if r.split_base.get(q).is_none_or(|&s| s == NO_SPLIT) {
                        coons_leaf(quad.i, quad.j, quad.size, &have, &mut w);
                    }
                }
            }
        }
    }
    border_strips(p, levels, rendered, &mut w);
    let total: f64 = w.iter().sum();
    w.iter().map(|x| (x / total) as f32).collect()
}

/// Layout centred: the light outside the inset lattice, a strip of width η = `border_strip` along
/// each side plus η² squares at the corners, with V extended outwards from the nearest lattice edge
/// (docs/method.md §7.1). Each leaf's boundary edge adds η × its 1-D rule along that edge: the two
/// corners for area weights, every rendered sample on the edge for Coons. Fully split, every sample
/// then weighs the same: the midpoint rule of the centred grid.
fn border_strips(p: &AdaptiveParams, levels: &[LevelReport], rendered: &[u32], w: &mut [f64]) {
    let eta = p.border_strip();
    if eta == 0.0 {
        return;
    }
    let mut have = vec![false; LATTICE_POINTS as usize];
    for &k in rendered {
        have[k as usize] = true;
    }
    let k = |x: u32, y: u32| (y * 17 + x) as usize;
    for r in levels {
        for (q, quad) in r.quads.iter().enumerate() {
            if r.split_base.get(q).is_some_and(|&s| s != NO_SPLIT) {
                continue;
            }
            let (i, j, size) = (quad.i, quad.j, quad.size);
            let len = size as f64 / 16.0;
            // Boundary edges of this leaf as (start, step).
            let mut edges = Vec::new();
            if j == 0 {
                edges.push(((i, 0), (1, 0)));
            }
            if j + size == 16 {
                edges.push(((i, 16), (1, 0)));
            }
            if i == 0 {
                edges.push(((0, j), (0, 1)));
            }
            if i + size == 16 {
                edges.push(((16, j), (0, 1)));
            }
            for ((x0, y0), (dx, dy)) in edges {
                let on: Vec<u32> = match p.weights {
                    Weights::Coons => (0..=size)
                        .filter(|&t| t == 0 || t == size || have[k(x0 + t * dx, y0 + t * dy)])
                        .collect(),
                    _ => vec![0, size],
                };
                for (n, &t) in on.iter().enumerate() {
                    let before = if n == 0 { t } else { on[n - 1] };
                    let after = if n + 1 == on.len() { t } else { on[n + 1] };
                    w[k(x0 + t * dx, y0 + t * dy)] +=
                        eta * len * (after - before) as f64 / (2.0 * size as f64);
                }
            }
        }
    }
    for (x, y) in [(0, 0), (16, 0), (0, 16), (16, 16)] {
        w[k(x, y)] += eta * eta;
    }
}

/// The integral of the Coons patch over one leaf (docs/method.md §3): half the composite
/// trapezoid rule along each of its four edges, through every rendered sample on the edge, minus a
/// quarter of its corners. Without samples hanging on its edges this is the trapezoid rule.
fn coons_leaf(i: u32, j: u32, size: u32, have: &[bool], w: &mut [f64]) {
    let area = (size as f64 / 16.0).powi(2);
    let k = |x: u32, y: u32| (y * 17 + x) as usize;
    // Each edge as (start, step): lattice points start + t·step for t = 0..=size.
    let edges = [
        ((i, j), (1, 0)),
        ((i, j + size), (1, 0)),
        ((i, j), (0, 1)),
        ((i + size, j), (0, 1)),
    ];
    for ((x0, y0), (dx, dy)) in edges {
        let on: Vec<u32> = (0..=size)
            .filter(|&t| t == 0 || t == size || have[k(x0 + t * dx, y0 + t * dy)])
            .collect();
        for (n, &t) in on.iter().enumerate() {
            let before = if n == 0 { t } else { on[n - 1] };
            let after = if n + 1 == on.len() { t } else { on[n + 1] };
            w[k(x0 + t * dx, y0 + t * dy)] +=
                0.5 * area * (after - before) as f64 / (2.0 * size as f64);
        }
    }
    for (x, y) in [(i, j), (i + size, j), (i, j + size), (i + size, j + size)] {
        w[k(x, y)] -= 0.25 * area;
    }
}

/// lcm of (2^l + 1)² for l = 0..=4 (4, 9, 25, 81, 289): the level rule's common denominator.
pub const LEVEL_LCM: i64 = 2_340_900;

/// Integer numerators of the weights on the corner-to-corner lattice (their common denominator
/// cancels in ŵ): level, LEVEL_LCM/(2^ℓ+1)²; area and Coons, 1024ths of the light (every quad size
/// is a power of two, so the rules of `sample_weights` are exact in these units).
/// kernels/weights.wgsl computes the same integers.
pub fn lattice_numerators(
    p: &AdaptiveParams,
    levels: &[LevelReport],
    sample_level: &[u32],
    rendered: &[u32],
) -> Vec<i64> {
    let mut w = vec![0i64; LATTICE_POINTS as usize];
    let k = |x: u32, y: u32| (y * 17 + x) as usize;
    if p.weights == Weights::Level {
        for &s in rendered {
            let d = (1i64 << sample_level[s as usize]) + 1;
            w[s as usize] = LEVEL_LCM / (d * d);
        }
        return w;
    }
    let mut have = vec![false; LATTICE_POINTS as usize];
    for &s in rendered {
        have[s as usize] = true;
    }
    for r in levels {
        for (q, quad) in r.quads.iter().enumerate() {
            if r.split_base.get(q).is_some_and(|&s| s != NO_SPLIT) {
                continue;
            }
            let (i, j, size) = (quad.i, quad.j, quad.size);
            let s2 = (size * size) as i64;
            if p.weights == Weights::Coons {
                for ((x0, y0), (dx, dy)) in [
                    ((i, j), (1, 0)),
                    ((i, j + size), (1, 0)),
                    ((i, j), (0, 1)),
                    ((i + size, j), (0, 1)),
                ] {
                    let on: Vec<u32> = (0..=size)
                        .filter(|&t| t == 0 || t == size || have[k(x0 + t * dx, y0 + t * dy)])
                        .collect();
                    for (n, &t) in on.iter().enumerate() {
                        let before = if n == 0 { t } else { on[n - 1] };
                        let after = if n + 1 == on.len() { t } else { on[n + 1] };
                        w[k(x0 + t * dx, y0 + t * dy)] += (size * (after - before)) as i64;
                    }
                }
            }
            for (x, y) in [(i, j), (i + size, j), (i, j + size), (i + size, j + size)] {
                w[k(x, y)] += if p.weights == Weights::Coons { -s2 } else { s2 };
            }
        }
    }
    w
}

/// `num / den` (den > 0, |num| < 2^31) rounded to the nearest f32, ties to even, by binary long
/// division: the `ratio` of kernels/weights.wgsl, step for step.
pub(crate) fn ratio_f32(num: i64, den: i64) -> f32 {
    if num == 0 {
        return 0.0;
    }
    let (mut r, mut d, mut e) = (num.unsigned_abs(), den as u64, 0i32);
    while r < d {
        r <<= 1;
        e -= 1;
    }
    while r >= 2 * d {
        d <<= 1;
        e += 1;
    }
    let mut m = 0u64;
    for _ in 0..24 {
        let bit = (r >= d) as u64;
        r -= bit * d;
        m = (m << 1) | bit;
        r <<= 1;
    }
    if r > d || (r == d && m & 1 == 1) {
        m += 1;
    }
    let v = m as f32 * 2f32.powi(e - 23);
    if num < 0 {
        -v
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::ratio_f32;

    #[test]
    fn ratio_is_correctly_rounded() {
        for (n, d) in [
            (1i64, 3i64),
            (2, 3),
            (1, 289),
            (585_225, 169_130_025),
            (-128, 1024),
            (7, 7),
            (1_234_567, 7_654_321),
            (1, 1 << 30),
        ] {
            let exact = n as f64 / d as f64; // correctly rounded in f64; these are far from f32 ties
            assert_eq!(ratio_f32(n, d), exact as f32, "{n}/{d}");
        }
        // A tie: 2^24 + 1 over 2^24 · 2 lies halfway between two f32s and rounds to even.
        assert_eq!(ratio_f32((1 << 24) + 1, 1 << 25), 0.5);
        assert_eq!(
            ratio_f32((1 << 24) + 3, 1 << 25),
            (((1u32 << 24) + 4) as f32) / (1u32 << 25) as f32
        );
    }
}
