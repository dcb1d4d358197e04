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
    let total: f64 = w.iter().sum();
    w.iter().map(|x| (x / total) as f32).collect()
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
