//! Twin of `kernels/regions.wgsl`: `measure` (each region's samples per side, finest texel and
//! receiver box) and `classify` (each geometry tile's class, the classes' lists and merged words).

use super::pcf::TapCentre;
use super::pcss::{blocker_search, midpoint, SearchArea};
use super::shadow::{pixel_lookup, tap_lit, LOOKUP_COMPARE};
use crate::gpu::structs::{GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use crate::stages::regions::{
    empty_class, empty_region, ordered, unordered, RegionsParams, CLASS_WORDS, REGION_WORDS,
};
// The budget's rules are the product's too (the CPU's budget and pictures); the twin tests
// compare them with the kernel's.
pub use crate::stages::regions_rules::{footprint, samples_of, total};
use glam::Vec2;

/// REGION_WORDS per region, as `measure` leaves them; `s` and `map` are the centre map's.
pub fn measure(
    frame: &GpuFrame,
    p: &RegionsParams,
    s: &GpuSample,
    map: &[f32],
    g: &GBufferCpu,
) -> Vec<u32> {
    let mut out: Vec<u32> = (0..p.region_count).flat_map(|_| empty_region()).collect();
    for index in 0..g.position.len() {
        let Some((lookup, t, slope)) = pixel_lookup(frame, s, g, index) else {
            continue;
        };
        let (x, y) = (index as u32 % g.width, index as u32 / g.width);
        let base = ((y / p.region) * p.regions_x + x / p.region) as usize * REGION_WORDS;
        let words = &mut out[base..base + REGION_WORDS];
        words[0] += 1;
        let f = footprint(g, index);
        if lookup.kind == LOOKUP_COMPARE {
            let z_r = lookup.depth_limit;
            let light = Vec2::new(p.light_u, p.light_v) * 0.5;
            let area = SearchArea {
                light,
                max_radius: p.max_radius,
                taps: p.blocker_taps,
            };
            let b = blocker_search(
                frame,
                s,
                map,
                area,
                TapCentre {
                    t,
                    limit: z_r,
                    slope,
                },
            );
            if f > 0.0 {
                words[2] = words[2].min(ordered(f / z_r));
            }
            if b.blockers > 0 {
                let z_b = b.sum / b.blockers as f32;
                let r = (light * (z_r - z_b) / (z_r * z_b) * (1.0 / s.texel_angle))
                    .min(Vec2::splat(p.max_radius));
                let nb = p.blocker_taps;
                let mut lit = 0.0f32;
                for j in 0..nb {
                    for i in 0..nb {
                        let o = Vec2::new(midpoint(i, nb, r.x), midpoint(j, nb, r.y));
                        lit += tap_lit(frame, s, map, z_r - o.length() * slope, t + o);
                    }
                }
                if lit > 0.0 && lit < (nb * nb) as f32 {
                    words[1] += 1;
                    let width = p.light_u.max(p.light_v) * (z_r - z_b).max(0.0) / z_b;
                    words[3] = words[3].min(ordered(width / z_r));
                }
            }
        }
        let q = g.position[index];
        for k in 0..3 {
            words[4 + k] = words[4 + k].min(ordered(q[k]));
            words[7 + k] = words[7 + k].max(ordered(q[k]));
        }
    }
    out
}

/// The class of a region that needs `n` samples per side: the first ladder entry at or above it.
pub fn class_of(p: &RegionsParams, n: u32) -> usize {
    let len = p.ladder_len as usize;
    (0..len)
        .find(|&c| c + 1 >= len || p.ladder[c] >= n)
        .unwrap_or(0)
}

/// `classify` on the geometry tiles `tiles`: CLASS_WORDS per class, and each class's tiles (sorted;
/// the GPU appends them in any order).
pub fn classify(
    p: &RegionsParams,
    width: u32,
    regions: &[u32],
    totals: [u32; 2],
    tiles: &[u32],
) -> (Vec<u32>, Vec<Vec<u32>>) {
    let classes = p.ladder_len as usize;
    let mut words: Vec<u32> = (0..classes).flat_map(|_| empty_class()).collect();
    let mut lists = vec![Vec::new(); classes];
    let tiles_x = width.div_ceil(8);
    for &tile in tiles {
        let (x, y) = ((tile % tiles_x) * 8, (tile / tiles_x) * 8);
        let base = ((y / p.region) * p.regions_x + x / p.region) as usize * REGION_WORDS;
        let r = &regions[base..base + REGION_WORDS];
        let n = samples_of(p, totals, r[0], r[1]);
        let c = class_of(p, n);
        lists[c].push(tile);
        let texel = if r[3] != u32::MAX {
            r[2].max(ordered(unordered(r[3]) / n as f32))
        } else {
            r[2]
        };
        let w = &mut words[c * CLASS_WORDS..(c + 1) * CLASS_WORDS];
        w[0] += 1;
        w[1] = w[1].min(texel);
        for k in 0..3 {
            w[2 + k] = w[2 + k].min(r[4 + k]);
            w[5 + k] = w[5 + k].max(r[7 + k]);
        }
    }
    for l in &mut lists {
        l.sort_unstable();
    }
    (words, lists)
}
