//! Twin of `kernels/shade.wgsl`.

use super::shadow::lit;
use crate::gpu::structs::{GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use glam::Vec4;

/// `visibility[p] += Σ_{i in range} weights[i] · lit_i(p)`; `maps[i]` is sample i's map.
pub fn shade(
    frame: &GpuFrame,
    samples: &[GpuSample],
    weights: &[f32],
    maps: &[Vec<f32>],
    g: &GBufferCpu,
    range: std::ops::Range<usize>,
    visibility: &mut [f32],
) {
    for (index, v) in visibility.iter_mut().enumerate() {
        if !g.is_geometry(index) {
            continue;
        }
        let p = Vec4::from(g.position[index]).truncate();
        let n = Vec4::from(g.normal[index]).truncate();
        let mut acc = *v;
        for i in range.clone() {
            acc += weights[i] * lit(frame, &samples[i], &maps[i], p, n) as f32;
        }
        *v = acc;
    }
}

/// Twin of `shade.wgsl` `from_masks`: Σ_k ŵ_k · bit_k(p), k ascending.
pub fn from_masks(weights: &[f32], masks: &[u32], g: &GBufferCpu) -> Vec<f32> {
    (0..g.position.len())
        .map(|index| {
            if !g.is_geometry(index) {
                return 0.0;
            }
            let mut v = 0.0f32;
            for k in 0..289u32 {
                if super::reproject_count::mask_bit(masks, index, k) == 1 {
                    v += weights[k as usize];
                }
            }
            v
        })
        .collect()
}

/// `geometry_tiles`: the 8×8 tiles (row-major index over the image's tiles) that hold a geometry
/// pixel, ascending.
pub fn geometry_tiles(g: &GBufferCpu) -> Vec<u32> {
    let tile = crate::stages::shade::TILE;
    let tiles_x = g.width.div_ceil(tile);
    let mut tiles: Vec<u32> = (0..g.position.len())
        .filter(|&i| g.is_geometry(i))
        .map(|i| (i as u32 / g.width / tile) * tiles_x + (i as u32 % g.width) / tile)
        .collect();
    tiles.sort_unstable();
    tiles.dedup();
    tiles
}
