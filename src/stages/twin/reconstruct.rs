//! Twin of `kernels/reconstruct.wgsl`.

use super::moments::{normalised_depth, FILTERED_ESM, FILTERED_EVSM, FILTERED_MSM, FILTERED_VSM};
use super::shadow::{pixel_lookup, LOOKUP_COMPARE, LOOKUP_OUTSIDE};
use crate::gpu::structs::{GpuFilter, GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use glam::{Vec2, Vec4};

fn fetch(m: &[[f32; 4]], size: u32, layer: u32, x: i32, y: i32) -> Vec4 {
    let n = size as i32;
    let (cx, cy) = (x.clamp(0, n - 1), y.clamp(0, n - 1));
    Vec4::from(m[(layer * size * size) as usize + (cy * n + cx) as usize])
}

fn bilinear(m: &[[f32; 4]], size: u32, layer: u32, t: Vec2) -> Vec4 {
    let x = t - Vec2::splat(0.5);
    let i = x.floor();
    let f = x - i;
    let (ix, iy) = (i.x as i32, i.y as i32);
    let a = fetch(m, size, layer, ix, iy);
    let b = fetch(m, size, layer, ix + 1, iy);
    let c = fetch(m, size, layer, ix, iy + 1);
    let d = fetch(m, size, layer, ix + 1, iy + 1);
    mix(mix(a, b, f.x), mix(c, d, f.x), f.y)
}

/// WGSL's `mix`: a·(1 − f) + b·f.
fn mix(a: Vec4, b: Vec4, f: f32) -> Vec4 {
    a * (1.0 - f) + b * f
}

/// Chebyshev's one-sided bound P(z_occ >= t) from a mean and a second moment.
pub fn chebyshev(mean: f32, second: f32, t: f32, min_variance: f32) -> f32 {
    if t <= mean {
        return 1.0;
    }
    let variance = (second - mean * mean).max(min_variance);
    let d = t - mean;
    variance / (variance + d * d)
}

fn reduce_bleeding(p: f32, bleed: f32) -> f32 {
    ((p - bleed) / (1.0 - bleed)).clamp(0.0, 1.0)
}

// The paper's digits, as in the kernel, so the two read alike (f32 rounds them the same).
#[allow(clippy::excessive_precision)]
pub fn msm_decode(m: Vec4) -> Vec4 {
    let q = Vec4::new(m.x - 0.035955884801, m.y, m.z, m.w);
    Vec4::new(
        0.2227744146 * q.x + 0.0771972861 * q.y + 0.7926986636 * q.z + 0.0319417555 * q.w,
        0.1549679261 * q.x + 0.1394629426 * q.y + 0.7963415838 * q.z - 0.1722823173 * q.w,
        0.1451988946 * q.x + 0.2120202157 * q.y + 0.7258694464 * q.z - 0.2758014811 * q.w,
        0.163127443 * q.x + 0.2591432266 * q.y + 0.6539092497 * q.z - 0.3376131734 * q.w,
    )
}

/// Hamburger 4MSM shadow intensity (occluded fraction) from biased moments `b` at depth `z`.
pub fn msm_intensity(b: Vec4, z: f32) -> f32 {
    let l32d22 = -b.x * b.y + b.z;
    let d22 = -b.x * b.x + b.y;
    let squared_variance = -b.y * b.y + b.w;
    let d33d22 = squared_variance * d22 - l32d22 * l32d22;
    let inv_d22 = 1.0 / d22;
    let l32 = l32d22 * inv_d22;
    let mut c = [1.0, z, z * z];
    c[1] -= b.x;
    c[2] -= b.y + l32 * c[1];
    c[1] *= inv_d22;
    c[2] *= d22 / d33d22;
    c[1] -= l32 * c[2];
    c[0] -= c[1] * b.x + c[2] * b.y;
    let p = c[1] / c[2];
    let q = c[0] / c[2];
    let r = (p * p * 0.25 - q).max(0.0).sqrt();
    let z1 = -p * 0.5 - r;
    let z2 = -p * 0.5 + r;
    let sw = if z2 < z {
        [z1, z, 1.0, 1.0]
    } else if z1 < z {
        [z, z1, 0.0, 1.0]
    } else {
        [0.0; 4]
    };
    let quotient = (sw[0] * z2 - b.x * (sw[0] + z2) + b.y) / ((z2 - sw[1]) * (z - z1));
    (sw[2] + sw[3] * quotient).clamp(0.0, 1.0)
}

/// V for every pixel (background 0) from the prefiltered planes `m`.
pub fn reconstruct(
    frame: &GpuFrame,
    filter: &GpuFilter,
    s: &GpuSample,
    m: &[[f32; 4]],
    g: &GBufferCpu,
) -> Vec<f32> {
    let size = frame.map_size;
    (0..g.position.len())
        .map(|index| {
            let Some((lookup, t, _)) = pixel_lookup(frame, s, g, index) else {
                return 0.0;
            };
            if lookup.kind != LOOKUP_COMPARE {
                return if lookup.kind == LOOKUP_OUTSIDE {
                    1.0
                } else {
                    0.0
                };
            }
            let z = normalised_depth(s, lookup.depth_limit);
            let e = bilinear(m, size, 0, t);
            match filter.kind {
                FILTERED_ESM => {
                    let m = glam::Mat4::from_cols_array_2d(&s.light_from_world);
                    let p = Vec4::from(g.position[index]).truncate();
                    let depth = Vec4::new(m.x_axis.w, m.y_axis.w, m.z_axis.w, m.w_axis.w)
                        .dot(Vec4::from((p, 1.0)));
                    let depth_z = Vec4::new(m.x_axis.z, m.y_axis.z, m.z_axis.z, m.w_axis.z)
                        .dot(Vec4::from((p, 1.0)));
                    let depth = if s.orthographic != 0 {
                        s.depth_lin_a * depth_z + s.depth_lin_b
                    } else {
                        depth
                    };
                    (e.x * (-filter.c_pos * normalised_depth(s, depth)).exp()).min(1.0)
                }
                FILTERED_VSM => reduce_bleeding(chebyshev(e.x, e.y, z, 1e-6), filter.bleed),
                FILTERED_EVSM => {
                    let w = 2.0 * z - 1.0;
                    let pos = (filter.c_pos * w).exp();
                    let neg = -(-filter.c_neg * w).exp();
                    let (dp, dn) = (1e-3 * filter.c_pos * pos, 1e-3 * filter.c_neg * neg);
                    let vp = chebyshev(e.x, e.y, pos, dp * dp);
                    let vn = chebyshev(e.z, e.w, neg, dn * dn);
                    reduce_bleeding(vp.min(vn), filter.bleed)
                }
                FILTERED_MSM => {
                    let b = mix(msm_decode(e), Vec4::splat(0.5), filter.moment_bias);
                    1.0 - msm_intensity(b, z)
                }
                _ => {
                    let zc = z - filter.depth_offset;
                    let mut sum = 0.0f32;
                    for l in 0..filter.layers {
                        let e = bilinear(m, size, l, t);
                        let k0 = 2 * l + 1;
                        if k0 <= filter.order {
                            let c = std::f32::consts::PI * (2 * k0 - 1) as f32;
                            sum += ((c * zc).sin() * e.x - (c * zc).cos() * e.y) / c;
                        }
                        if k0 < filter.order {
                            let c = std::f32::consts::PI * (2 * k0 + 1) as f32;
                            sum += ((c * zc).sin() * e.z - (c * zc).cos() * e.w) / c;
                        }
                    }
                    (0.5 - 2.0 * sum).clamp(0.0, 1.0)
                }
            }
        })
        .collect()
}
