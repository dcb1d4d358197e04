//! Twin of `kernels/env_shadowmaps.wgsl`.

use super::pcf::{pcf_taps, TapCentre};
use super::shadow::{pixel_lookup, LOOKUP_COMPARE, LOOKUP_OUTSIDE};
use crate::gpu::structs::{GpuEnvLight, GpuEnvParams, GpuFilter, GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use glam::Vec3;

/// The filter's settings and tap offsets (the PCF family's, as `pcf` takes them).
pub struct Filter<'a> {
    pub settings: &'a GpuFilter,
    pub disk: &'a [[f32; 2]],
}

/// Each light's sample record and map (`maps[k]` is sample k's map, row-major).
#[derive(Clone, Copy, Debug)]
pub struct LightMaps<'a> {
    pub samples: &'a [GpuSample],
    pub maps: &'a [Vec<f32>],
}

/// V per pixel from the K maps (`maps[k]` is sample k's map, row-major).
pub fn env_shadowmaps(
    frame: &GpuFrame,
    params: &GpuEnvParams,
    filter: Filter,
    light_maps: LightMaps,
    lights: &[GpuEnvLight],
    ao: &[f32],
    g: &GBufferCpu,
) -> Vec<f32> {
    let LightMaps { samples, maps } = light_maps;
    let width = g.width as usize;
    (0..g.position.len())
        .map(|index| {
            if !g.is_geometry(index) {
                return 0.0;
            }
            let n = Vec3::from_slice(&g.normal[index][..3]);
            let (mut num, mut den) = (0.0f32, 0.0f32);
            for k in 0..params.light_count as usize {
                let s = &samples[k];
                let Some((lookup, t, slope)) = pixel_lookup(frame, s, g, index) else {
                    return 0.0;
                };
                let l = lights[k].direction;
                let c = n.dot(Vec3::new(l[0], l[1], l[2]));
                if c <= 0.0 {
                    continue;
                }
                let w = l[3] * c;
                den += w;
                if lookup.kind == LOOKUP_OUTSIDE {
                    num += w;
                    continue;
                }
                if lookup.kind != LOOKUP_COMPARE {
                    continue;
                }
                let pixel = ((index % width) as u32, (index / width) as u32);
                let (lit, taps) = pcf_taps(
                    frame,
                    filter.settings,
                    s,
                    &maps[k],
                    filter.disk,
                    TapCentre {
                        t,
                        limit: lookup.depth_limit,
                        slope,
                    },
                    pixel,
                );
                num += w * lit / taps;
            }
            let v = if den > 0.0 { num / den } else { 0.0 };
            if params.use_ao != 0 {
                v * ao[index]
            } else {
                v
            }
        })
        .collect()
}
