//! Sample weights for scope = global: the seed's level rule, or leaf-quad areas.

use super::levels::LevelReport;
use crate::methods::{AdaptiveParams, Weights};
use crate::compute::buffers::{LATTICE_POINTS, NO_SPLIT};

/// ŵ_k for every lattice index (0 where no map was rendered); Σ ŵ = 1.
pub fn sample_weights(p: &AdaptiveParams, levels: &[LevelReport], sample_level: &[u32], rendered: &[u32]) -> Vec<f32> {
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
            if !r.split_base.get(q).is_none_or(|&s| s == NO_SPLIT) {
                continue;
            }
            let (i, j, size) = (quad.i, quad.j, quad.size);
            let len = size as f64 / 16.0;
            // Boundary edges of this leaf as (start, step).
            let mut edges = Vec::new();
            if j == 0 { edges.push(((i, 0), (1, 0))); }
            if j + size == 16 { edges.push(((i, 16), (1, 0))); }
            if i == 0 { edges.push(((0, j), (0, 1))); }
            if i + size == 16 { edges.push(((16, j), (0, 1))); }
            for ((x0, y0), (dx, dy)) in edges {
                let on: Vec<u32> = match p.weights {
                    Weights::Coons => (0..=size).filter(|&t| t == 0 || t == size || have[k(x0 + t * dx, y0 + t * dy)]).collect(),
                    _ => vec![0, size],
                };
                for (n, &t) in on.iter().enumerate() {
                    let before = if n == 0 { t } else { on[n - 1] };
                    let after = if n + 1 == on.len() { t } else { on[n + 1] };
                    w[k(x0 + t * dx, y0 + t * dy)] += eta * len * (after - before) as f64 / (2.0 * size as f64);
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
    let edges = [((i, j), (1, 0)), ((i, j + size), (1, 0)), ((i, j), (0, 1)), ((i + size, j), (0, 1))];
    for ((x0, y0), (dx, dy)) in edges {
        let on: Vec<u32> = (0..=size).filter(|&t| t == 0 || t == size || have[k(x0 + t * dx, y0 + t * dy)]).collect();
        for (n, &t) in on.iter().enumerate() {
            let before = if n == 0 { t } else { on[n - 1] };
            let after = if n + 1 == on.len() { t } else { on[n + 1] };
            w[k(x0 + t * dx, y0 + t * dy)] += 0.5 * area * (after - before) as f64 / (2.0 * size as f64);
        }
    }
    for (x, y) in [(i, j), (i + size, j), (i, j + size), (i + size, j + size)] {
        w[k(x, y)] -= 0.25 * area;
    }
}
