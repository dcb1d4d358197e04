//! The per-region rules of `kernels/regions.wgsl` on the CPU, same operation order: a pixel's
//! world footprint, the weight total and the samples per side. The product reads them for the
//! regions budget and its pictures; the twin (`stages::twin::regions`) is tested against the
//! kernel with them.

use crate::render::gbuffer::GBufferCpu;
use crate::stages::regions::{RegionsParams, REGION_WORDS, SAMPLING_ORDER, WEIGHT_SCALE};
use glam::Vec4;

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

/// `total`: [Σ WEIGHT_SCALE · P^0.4 A^0.6 over regions with a penumbra, rounded each, Σ A].
pub fn total(p: &RegionsParams, regions: &[u32]) -> [u32; 2] {
    let mut t = [0u32; 2];
    for r in regions.chunks(REGION_WORDS).take(p.region_count as usize) {
        if r[1] > 0 {
            t[0] +=
                (WEIGHT_SCALE * (r[1] as f32).powf(0.4) * (r[0] as f32).powf(0.6)).round() as u32;
        }
        t[1] += r[0];
    }
    t
}

/// Samples per side of a region (`samples_of`): k (P/A)^0.2, k³ = Σ P^0.4 A^0.6 / (12 T² N).
pub fn samples_of(p: &RegionsParams, totals: [u32; 2], area: u32, penumbra: u32) -> u32 {
    if penumbra == 0 {
        return 1;
    }
    let sum = totals[0] as f32 / WEIGHT_SCALE;
    let n_geo = totals[1].max(1) as f32;
    let k = (sum / (12.0 * p.target * p.target * n_geo)).powf(1.0 / (2.0 * SAMPLING_ORDER));
    let n = k * (penumbra as f32 / area as f32).powf(0.2);
    (n.min(p.max_n as f32).ceil() as u32).clamp(1, p.max_n)
}
