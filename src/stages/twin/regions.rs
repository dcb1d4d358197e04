//! Twin of `kernels/regions.wgsl`: `measure` (each region's samples per side, finest texel and
//! receiver box) and `classify` (each geometry tile's class, the classes' lists and merged words).

use super::pcss::blocker_search;
use super::shadow::{pixel_lookup, LOOKUP_COMPARE};
use crate::gpu::structs::{GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use crate::stages::regions::{empty_words, ordered, RegionsParams, REGION_WORDS};
use glam::{Vec2, Vec4};

/// World distance from pixel `index` to its neighbour `(dx, dy)`, or -1 off screen or on background.
fn gap(g: &GBufferCpu, index: usize, dx: i32, dy: i32) -> f32 {
    let (w, h) = (g.width as i32, g.height as i32);
    let (x, y) = ((index as i32) % w + dx, (index as i32) / w + dy);
    if x < 0 || y < 0 || x >= w || y >= h {
        return -1.0;
    }
    let q = (y * w + x) as usize;
    if g.position[q][3] != 0.0 {
        (Vec4::from(g.position[q]).truncate() - Vec4::from(g.position[index]).truncate()).length()
    } else {
        -1.0
    }
}

fn nearer(a: f32, b: f32) -> f32 {
    if a < 0.0 {
        b
    } else if b < 0.0 {
        a
    } else {
        a.min(b)
    }
}

/// A geometry pixel's world footprint: the larger of its across and down gaps to the nearer
/// neighbour on each axis (0 for a lone pixel).
pub fn footprint(g: &GBufferCpu, index: usize) -> f32 {
    let fx = nearer(gap(g, index, -1, 0), gap(g, index, 1, 0));
    let fy = nearer(gap(g, index, 0, -1), gap(g, index, 0, 1));
    fx.max(fy).max(0.0)
}

/// REGION_WORDS per region, as `measure` leaves them; `s` and `map` are the centre map's.
pub fn measure(frame: &GpuFrame, p: &RegionsParams, s: &GpuSample, map: &[f32], g: &GBufferCpu) -> Vec<u32> {
    let regions = p.regions_x * g.height.div_ceil(p.region);
    let mut out: Vec<u32> = (0..regions).flat_map(|_| empty_words()).collect();
    for index in 0..g.position.len() {
        let Some((lookup, t, slope)) = pixel_lookup(frame, s, g, index) else { continue };
        let f = footprint(g, index);
        let (mut n, mut width, mut z_r) = (1u32, 0.0f32, 1.0f32);
        if lookup.kind == LOOKUP_COMPARE {
            z_r = lookup.depth_limit;
            let light = Vec2::new(p.light_u, p.light_v) * 0.5;
            let b = blocker_search(frame, s, map, light, p.max_radius, p.blocker_taps, z_r, t, slope);
            if b.blockers > 0 && b.blockers < b.taps {
                let z_b = b.sum / b.blockers as f32;
                width = p.light_u.max(p.light_v) * (z_r - z_b).max(0.0) / z_b;
                let pixels = if f > 0.0 { width / f } else { 0.0 };
                n = ((pixels / p.step).min(p.max_n as f32).ceil() as u32).clamp(1, p.max_n);
            }
        }
        let texel = f.max(width / n as f32) / z_r;
        let (x, y) = (index as u32 % g.width, index as u32 / g.width);
        let base = ((y / p.region) * p.regions_x + x / p.region) as usize * REGION_WORDS;
        let words = &mut out[base..base + REGION_WORDS];
        words[0] = words[0].max(n);
        if texel > 0.0 {
            words[1] = words[1].min(ordered(texel));
        }
        let q = g.position[index];
        for k in 0..3 {
            words[2 + k] = words[2 + k].min(ordered(q[k]));
            words[5 + k] = words[5 + k].max(ordered(q[k]));
        }
    }
    out
}

/// The class of a region that needs `n` samples per side: the first ladder entry at or above it.
pub fn class_of(p: &RegionsParams, n: u32) -> usize {
    let len = p.ladder_len as usize;
    (0..len).find(|&c| c + 1 >= len || p.ladder[c] >= n).unwrap_or(0)
}

/// `classify` on the geometry tiles `tiles`: REGION_WORDS per class, and each class's tiles (sorted;
/// the GPU appends them in any order).
pub fn classify(p: &RegionsParams, width: u32, regions: &[u32], tiles: &[u32]) -> (Vec<u32>, Vec<Vec<u32>>) {
    let classes = p.ladder_len as usize;
    let mut words: Vec<u32> = (0..classes).flat_map(|_| empty_words()).collect();
    let mut lists = vec![Vec::new(); classes];
    let tiles_x = width.div_ceil(8);
    for &tile in tiles {
        let (x, y) = ((tile % tiles_x) * 8, (tile / tiles_x) * 8);
        let base = ((y / p.region) * p.regions_x + x / p.region) as usize * REGION_WORDS;
        let r = &regions[base..base + REGION_WORDS];
        let c = class_of(p, r[0]);
        lists[c].push(tile);
        let w = &mut words[c * REGION_WORDS..(c + 1) * REGION_WORDS];
        w[0] += 1;
        w[1] = w[1].min(r[1]);
        for k in 2..5 {
            w[k] = w[k].min(r[k]);
            w[k + 3] = w[k + 3].max(r[k + 3]);
        }
    }
    for l in &mut lists {
        l.sort_unstable();
    }
    (words, lists)
}
