//! Twin of `kernels/pcss.wgsl`.

use super::pcf::TapCentre;
use super::shadow::{depth_passes, pixel_lookup, tap_lit, LOOKUP_COMPARE, LOOKUP_OUTSIDE};
use crate::gpu::structs::{GpuFilter, GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use glam::Vec2;

pub fn midpoint(i: u32, n: u32, r: f32) -> f32 {
    -r + 2.0 * r * (i as f32 + 0.5) / n as f32
}

/// What a blocker search found: the sum of the blockers' linear depths, their count, and the taps
/// that fell inside the map.
pub struct Blockers {
    pub sum: f32,
    pub blockers: u32,
    pub taps: u32,
}

/// Where a blocker search looks: a light of half-size `light`, a radius of at most `max_radius`
/// texels, `taps`×`taps` taps.
#[derive(Clone, Copy, Debug)]
pub struct SearchArea {
    pub light: Vec2,
    pub max_radius: f32,
    pub taps: u32,
}

/// pcss's blocker search (and the regions' `measure`): `area.taps`² taps over the map region
/// through which a receiver at linear depth `at.limit` and map position `at.t` sees the light.
pub fn blocker_search(
    frame: &GpuFrame,
    s: &GpuSample,
    map: &[f32],
    area: SearchArea,
    at: TapCentre,
) -> Blockers {
    let SearchArea {
        light,
        max_radius,
        taps: nb,
    } = area;
    let TapCentre {
        t,
        limit: z_r,
        slope,
    } = at;
    let size = frame.map_size as f32;
    let ortho = s.orthographic != 0;
    let near = if ortho {
        s.depth_lin_b
    } else {
        s.depth_lin_a / s.depth_lin_b
    };
    let per_angle = 1.0 / s.texel_angle;
    let search = (light * (z_r - near).max(0.0) / if ortho { 1.0 } else { z_r * near } * per_angle)
        .min(Vec2::splat(max_radius));
    let mut out = Blockers {
        sum: 0.0,
        blockers: 0,
        taps: 0,
    };
    for j in 0..nb {
        for i in 0..nb {
            let o = Vec2::new(midpoint(i, nb, search.x), midpoint(j, nb, search.y));
            let texel = (t + o).floor();
            if texel.x < 0.0 || texel.y < 0.0 || texel.x >= size || texel.y >= size {
                continue;
            }
            out.taps += 1;
            let stored = map[texel.y as usize * frame.map_size as usize + texel.x as usize];
            if !depth_passes(s, z_r - o.length() * slope, stored) {
                out.sum += if ortho {
                    s.depth_lin_a * stored + s.depth_lin_b
                } else {
                    s.depth_lin_a / (stored + s.depth_lin_b)
                };
                out.blockers += 1;
            }
        }
    }
    out
}

/// V for every pixel (background 0), as `pcss.wgsl` writes it.
pub fn pcss(
    frame: &GpuFrame,
    filter: &GpuFilter,
    s: &GpuSample,
    map: &[f32],
    g: &GBufferCpu,
) -> Vec<f32> {
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
            let z_r = lookup.depth_limit;
            let ortho = s.orthographic != 0;
            let per_angle = 1.0 / s.texel_angle;
            let light = Vec2::new(filter.light_u, filter.light_v) * 0.5;
            let area = SearchArea {
                light,
                max_radius: filter.max_radius,
                taps: filter.blocker_taps,
            };
            let search = blocker_search(
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
            let (blocker_sum, blockers) = (search.sum, search.blockers);
            if blockers == 0 {
                return 1.0;
            }
            let z_b = blocker_sum / blockers as f32;
            let r = (light * (z_r - z_b) / if ortho { 1.0 } else { z_r * z_b } * per_angle)
                .min(Vec2::splat(filter.max_radius));
            let n = filter.taps;
            let mut lit = 0.0f32;
            for j in 0..n {
                for i in 0..n {
                    let o = Vec2::new(midpoint(i, n, r.x), midpoint(j, n, r.y));
                    lit += tap_lit(frame, s, map, z_r - o.length() * slope, t + o);
                }
            }
            lit / (n * n) as f32
        })
        .collect()
}
