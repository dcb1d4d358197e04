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
    }
    let total: f64 = w.iter().sum();
    w.iter().map(|x| (x / total) as f32).collect()
}
