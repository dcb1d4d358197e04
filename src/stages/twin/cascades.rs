//! Twin of `kernels/cascades.wgsl`.

use super::pcf::{pcf_taps, TapCentre};
use super::shadow::{pixel_lookup, shadow_compare, LOOKUP_COMPARE, LOOKUP_OUTSIDE};
use crate::gpu::structs::{GpuCascades, GpuFilter, GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use crate::stages::cascades::{FILTER_HARD, NO_CASCADE};
use glam::{Vec3, Vec4};

/// The cascade of a point at view depth `depth`, as `cascade_of`.
pub fn cascade_of(c: &GpuCascades, depth: f32) -> u32 {
    (0..c.count.saturating_sub(1))
        .filter(|&i| depth > c.ends[i as usize / 4][i as usize % 4])
        .count() as u32
}

/// V (background 0) and the cascade of every pixel (`NO_CASCADE` on background). `maps[i]` is
/// cascade i's map, `samples[i]` its sample.
pub fn cascades(
    frame: &GpuFrame,
    filter: &GpuFilter,
    c: &GpuCascades,
    samples: &[GpuSample],
    maps: &[Vec<f32>],
    disk: &[[f32; 2]],
    g: &GBufferCpu,
) -> (Vec<f32>, Vec<u32>) {
    let w = g.width as usize;
    let (eye, forward) = (
        Vec4::from(c.eye).truncate(),
        Vec4::from(c.forward).truncate(),
    );
    (0..g.position.len())
        .map(|index| {
            if !g.is_geometry(index) {
                return (0.0, NO_CASCADE);
            }
            let p = Vec3::from_slice(&g.position[index][..3]);
            let k = cascade_of(c, (p - eye).dot(forward));
            let (s, map) = (&samples[k as usize], &maps[k as usize]);
            let (lookup, t, slope) = pixel_lookup(frame, s, g, index).expect("a geometry pixel");
            if lookup.kind != LOOKUP_COMPARE {
                return (
                    if lookup.kind == LOOKUP_OUTSIDE {
                        1.0
                    } else {
                        0.0
                    },
                    k,
                );
            }
            if c.filtering == FILTER_HARD {
                let size = frame.map_size as usize;
                let stored = map[lookup.texel[1] as usize * size + lookup.texel[0] as usize];
                return (shadow_compare(s, &lookup, stored) as f32, k);
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
            (lit / count, k)
        })
        .unzip()
}
