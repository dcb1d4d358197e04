//! Twin of `kernels/subdivide.wgsl`. The GPU appends in scheduling order, so callers compare the
//! children and new samples as sorted sets.

use super::quad_corner;
use crate::gpu::structs::GpuQuad;
use crate::stages::adaptive_buffers::{quad_node, HELD_WORDS, NO_SPLIT, QUAD_CAPACITY};

pub use crate::stages::subdivide::SplitRule;

#[derive(Debug, Default)]
pub struct SubdivideOut {
    pub next_quads: Vec<GpuQuad>,
    pub new_samples: Vec<u32>,
    /// First child index per quad, or NO_SPLIT.
    pub split_base: Vec<u32>,
    pub overflow: bool,
}

/// The level a subdivide splits at and how: quads of `level` split while `level < max_level`, by
/// `rule`; `geometry_pixels` is the share rules' denominator (reproject_count counts it at level 0).
#[derive(Clone, Copy, Debug)]
pub struct SplitLevel {
    pub level: u32,
    pub max_level: u32,
    pub rule: SplitRule,
    pub geometry_pixels: u32,
}

/// `lattice_state` (requested samples) and `sample_level` are updated in place, as the kernel's atomics.
pub fn subdivide(
    at: &SplitLevel,
    quads: &[GpuQuad],
    counters: &[u32],
    lattice_state: &mut [u32],
    sample_level: &mut [u32],
) -> SubdivideOut {
    subdivide_held(
        at,
        &Held::every(),
        quads,
        counters,
        lattice_state,
        sample_level,
    )
}

/// The hysteresis (`adaptive:hold`): the previous frame's split quads, one bit per quad node
/// (`quad_node`), and the margin a quad not among them must pass its threshold by.
#[derive(Clone, Debug)]
pub struct Held {
    pub bits: Vec<u32>,
    pub hold: u32,
}

impl Held {
    /// Every quad counts as split before: no margin anywhere (the first frame, or `hold = 0`).
    pub fn every() -> Held {
        Held {
            bits: vec![u32::MAX; HELD_WORDS as usize],
            hold: 0,
        }
    }

    fn margin(&self, quad: &GpuQuad) -> u32 {
        let node = quad_node(quad.i, quad.j, quad.size);
        if (self.bits[(node / 32) as usize] >> (node % 32)) & 1 == 1 {
            0
        } else {
            self.hold
        }
    }
}

/// `subdivide` with the previous frame's split quads `held`.
pub fn subdivide_held(
    at: &SplitLevel,
    held: &Held,
    quads: &[GpuQuad],
    counters: &[u32],
    lattice_state: &mut [u32],
    sample_level: &mut [u32],
) -> SubdivideOut {
    let SplitLevel {
        level,
        max_level,
        rule,
        geometry_pixels,
    } = *at;
    let mut out = SubdivideOut::default();
    let mut request = |i: u32, j: u32, out: &mut SubdivideOut| {
        let k = (j * 17 + i) as usize;
        if lattice_state[k] == 0 {
            lattice_state[k] = 1;
            out.new_samples.push(k as u32);
        }
    };
    for (q, quad) in quads.iter().enumerate() {
        for c in 0..4 {
            let k = quad_corner(quad, c) as usize;
            sample_level[k] = sample_level[k].max(level);
        }
        let margin = held.margin(quad);
        let split = level < max_level
            && quad.size > 1
            && match rule {
                SplitRule::Always => true,
                SplitRule::Never => false,
                SplitRule::Threshold(p_m) => counters[q] > p_m && counters[q] - p_m > margin,
                SplitRule::Share(share) => {
                    counters[q] as f32 - margin as f32 > geometry_pixels as f32 * share
                }
            };
        out.split_base.push(NO_SPLIT);
        if split {
            let base = out.next_quads.len() as u32;
            if base + 4 > QUAD_CAPACITY {
                out.overflow = true;
                continue;
            }
            let h = quad.size / 2;
            let q = q as u32;
            out.next_quads.extend([
                GpuQuad {
                    i: quad.i,
                    j: quad.j,
                    size: h,
                    parent: q,
                },
                GpuQuad {
                    i: quad.i + h,
                    j: quad.j,
                    size: h,
                    parent: q,
                },
                GpuQuad {
                    i: quad.i,
                    j: quad.j + h,
                    size: h,
                    parent: q,
                },
                GpuQuad {
                    i: quad.i + h,
                    j: quad.j + h,
                    size: h,
                    parent: q,
                },
            ]);
            out.split_base[q as usize] = base;
            request(quad.i + h, quad.j, &mut out);
            request(quad.i, quad.j + h, &mut out);
            request(quad.i + h, quad.j + h, &mut out);
            request(quad.i + 2 * h, quad.j + h, &mut out);
            request(quad.i + h, quad.j + 2 * h, &mut out);
        }
    }
    out.new_samples.sort_unstable();
    out
}
