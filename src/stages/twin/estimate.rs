//! Twin of `kernels/estimate.wgsl`: per pixel, the sums the error estimate is made of
//! (docs/error-estimate.md).

use super::shadow::{
    lit, shadow_lookup, shadow_lookup_uv, slope_per_texel, tap_lit, LOOKUP_COMPARE,
};
use crate::gpu::structs::{GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use glam::{Vec2, Vec3, Vec4};

/// Twin of `bilinear`: the four texels around the lookup point, each compared against the limit
/// moved along the receiver's slope by the tap's distance, weighted by the point's place between
/// their centres; the same operations in the same order.
pub fn bilinear(frame: &GpuFrame, s: &GpuSample, map: &[f32], limit: f32, p: Vec3, n: Vec3) -> f32 {
    let uv = shadow_lookup_uv(frame, s, p, n);
    let slope = slope_per_texel(frame, s, p, n);
    let base = (uv - Vec2::splat(0.5)).floor() + Vec2::splat(0.5);
    let frac = uv - base;
    let tap = |t: Vec2| tap_lit(frame, s, map, limit - (t - uv).length() * slope, t);
    let mut f = (1.0 - frac.x) * (1.0 - frac.y) * tap(base);
    f += frac.x * (1.0 - frac.y) * tap(base + Vec2::new(1.0, 0.0));
    f += (1.0 - frac.x) * frac.y * tap(base + Vec2::new(0.0, 1.0));
    f += frac.x * frac.y * tap(base + Vec2::new(1.0, 1.0));
    f
}

/// Sample i at p: the frame's test v, the bilinear test f (v where the lookup compares nothing)
/// and the test v₂ with doubled bias and normal offset.
pub fn tests(frame: &GpuFrame, s: &GpuSample, map: &[f32], p: Vec3, n: Vec3) -> (f32, f32, f32) {
    let v = lit(frame, s, map, p, n) as f32;
    let lookup = shadow_lookup(frame, s, p, n);
    let f = if lookup.kind == LOOKUP_COMPARE {
        bilinear(frame, s, map, lookup.depth_limit, p, n)
    } else {
        v
    };
    let doubled = GpuFrame {
        bias_constant: frame.bias_constant * 2.0,
        bias_slope: frame.bias_slope * 2.0,
        normal_offset: frame.normal_offset * 2.0,
        ..*frame
    };
    // The doubled lookup reads the same map: `lit` indexes it with the frame's map size.
    let v2 = lit(&doubled, s, map, p, n) as f32;
    (v, f, v2)
}

/// A fixed sample set as the estimate reads it: each sample's record, weight, split shares and map.
#[derive(Clone, Copy, Debug)]
pub struct SampleSet<'a> {
    pub samples: &'a [GpuSample],
    pub weights: &'a [f32],
    pub split: &'a [[f32; 2]],
    pub maps: &'a [Vec<f32>],
}

/// `sums[p] += Σ_{i in range}` (split[i].x · v_i, split[i].y · v_i,
/// weights[i] · q_i, weights[i] · b_i, split[i].x · q_i, split[i].y · q_i, split[i].x · b_i,
/// split[i].y · b_i), q_i = v_i − f_i and b_i = v₂_i − v_i, sample by sample.
pub fn estimate(
    frame: &GpuFrame,
    set: &SampleSet,
    g: &GBufferCpu,
    range: std::ops::Range<usize>,
    sums: &mut [crate::stages::estimate::Sums],
) {
    let SampleSet {
        samples,
        weights,
        split,
        maps,
    } = *set;
    for (index, acc) in sums.iter_mut().enumerate() {
        if !g.is_geometry(index) {
            continue;
        }
        let p = Vec4::from(g.position[index]).truncate();
        let n = Vec4::from(g.normal[index]).truncate();
        let mut a = *acc;
        for i in range.clone() {
            let (v, f, v2) = tests(frame, &samples[i], &maps[i], p, n);
            let (q, b, [sx, sy]) = (v - f, v2 - v, split[i]);
            a = [
                a[0] + sx * v,
                a[1] + sy * v,
                a[2] + weights[i] * q,
                a[3] + weights[i] * b,
                a[4] + sx * q,
                a[5] + sy * q,
                a[6] + sx * b,
                a[7] + sy * b,
            ];
        }
        *acc = a;
    }
}
