//! Twin of `kernels/pcf.wgsl`.

use super::shadow::{pixel_lookup, pixel_random, tap_lit, LOOKUP_COMPARE, LOOKUP_OUTSIDE};
use crate::gpu::structs::{GpuFilter, GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use glam::Vec2;

pub const PCF_BOX: u32 = 0;
pub const PCF_BILINEAR: u32 = 1;
pub const PCF_POISSON: u32 = 2;
pub const PCF_STRATIFIED: u32 = 3;
pub const PCF_ROTATED: u32 = 4;

fn grid_offset(i: u32, n: u32, r: f32) -> f32 {
    if n <= 1 {
        return 0.0;
    }
    -r + 2.0 * r * i as f32 / (n - 1) as f32
}

/// The comparison sampler's bilinear PCF: four texel tests around `t`, edges clamped.
fn bilinear_lit(frame: &GpuFrame, s: &GpuSample, map: &[f32], reference: f32, t: Vec2) -> f32 {
    let size = frame.map_size as i32;
    let x = t - Vec2::splat(0.5);
    let i = x.floor();
    let f = x - i;
    let test = |dx: i32, dy: i32| {
        let cx = (i.x as i32 + dx).clamp(0, size - 1);
        let cy = (i.y as i32 + dy).clamp(0, size - 1);
        if reference <= map[(cy * size + cx) as usize] {
            1.0
        } else {
            0.0
        }
    };
    let _ = s;
    let top = test(0, 0) * (1.0 - f.x) + test(1, 0) * f.x;
    let bottom = test(0, 1) * (1.0 - f.x) + test(1, 1) * f.x;
    top * (1.0 - f.y) + bottom * f.y
}

/// Where a pixel's taps centre: map position `t`, the depth limit there and its slope per texel
/// (each tap's limit moves by its offset's length times `slope`).
#[derive(Clone, Copy, Debug)]
pub struct TapCentre {
    pub t: Vec2,
    pub limit: f32,
    pub slope: f32,
}

/// Lit taps and tap count of `filter`'s pattern around map position `at.t` (pixel (x, y) seeds the
/// stratified and rotated patterns), as `shared/pcf_taps.wgsl` `pcf_taps` sums them.
pub fn pcf_taps(
    frame: &GpuFrame,
    filter: &GpuFilter,
    s: &GpuSample,
    map: &[f32],
    disk: &[[f32; 2]],
    at: TapCentre,
    (x, y): (u32, u32),
) -> (f32, f32) {
    let TapCentre { t, limit, slope } = at;
    let mut lit = 0.0f32;
    let count = if filter.kind == PCF_BOX || filter.kind == PCF_BILINEAR {
        let n = filter.taps;
        let size = frame.map_size as f32;
        for j in 0..n {
            for i in 0..n {
                let o = Vec2::new(
                    grid_offset(i, n, filter.radius),
                    grid_offset(j, n, filter.radius),
                );
                let tap_limit = limit - o.length() * slope;
                lit += if filter.kind == PCF_BOX {
                    tap_lit(frame, s, map, tap_limit, t + o)
                } else {
                    let reference = if s.orthographic != 0 {
                        (tap_limit - s.depth_lin_b) / s.depth_lin_a
                    } else {
                        s.depth_lin_a / tap_limit - s.depth_lin_b
                    };
                    bilinear_lit(frame, s, map, reference, (t + o) / size * size)
                };
            }
        }
        n * n
    } else {
        for i in 0..filter.taps {
            let d = match filter.kind {
                PCF_POISSON => Vec2::from(disk[i as usize]),
                PCF_STRATIFIED => {
                    let k = (filter.order as f32 * pixel_random(x, y, i)) as u32 % filter.order;
                    Vec2::from(disk[k as usize])
                }
                _ => {
                    let p = Vec2::from(disk[i as usize]);
                    let angle = std::f32::consts::TAU * pixel_random(x, y, i);
                    let (sn, c) = angle.sin_cos();
                    Vec2::new(p.x * c + p.y * sn, -p.x * sn + p.y * c)
                }
            };
            let o = d * filter.radius;
            lit += tap_lit(frame, s, map, limit - o.length() * slope, t + o);
        }
        filter.taps
    };
    (lit, count as f32)
}

/// V for every pixel (background 0), as `pcf.wgsl` `main` writes it.
pub fn pcf(
    frame: &GpuFrame,
    filter: &GpuFilter,
    s: &GpuSample,
    map: &[f32],
    disk: &[[f32; 2]],
    g: &GBufferCpu,
) -> Vec<f32> {
    let w = g.width as usize;
    (0..g.position.len())
        .map(|index| {
            let Some((lookup, t, slope)) = pixel_lookup(frame, s, g, index) else {
                return 0.0;
            };
            if lookup.kind != LOOKUP_COMPARE {
                return if lookup.kind == LOOKUP_OUTSIDE {
                    1.0
                } else {
                    0.0
                };
            }
            let pixel = ((index % w) as u32, (index / w) as u32);
            let (lit, count) = pcf_taps(
                frame,
                filter,
                s,
                map,
                disk,
                TapCentre {
                    t,
                    limit: lookup.depth_limit,
                    slope,
                },
                pixel,
            );
            if filter.darkening > 0.0 {
                (1.0 - filter.darkening * (count - lit)).clamp(0.0, 1.0)
            } else {
                lit / count
            }
        })
        .collect()
}
