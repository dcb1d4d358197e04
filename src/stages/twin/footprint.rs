//! Twin of `kernels/footprint.wgsl`: each slot's culling tiles from every geometry pixel.

use super::shadow::{shadow_lookup, LOOKUP_COMPARE};
use crate::gpu::structs::{GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use crate::stages::adaptive_buffers::{CULL_TILES, CULL_TILE_WORDS};
use glam::Vec4;

/// CULL_TILE_WORDS words per sample of `samples` (slot n = samples[n]): 0 where no geometry pixel
/// of `g` looks up a texel, else the largest positive depth limit (f32 bits) tested there.
pub fn footprint(frame: &GpuFrame, samples: &[GpuSample], g: &GBufferCpu) -> Vec<u32> {
    let words = CULL_TILE_WORDS as usize;
    let mut tiles = vec![0u32; samples.len() * words];
    for (z, s) in samples.iter().enumerate() {
        for i in (0..g.position.len()).filter(|&i| g.is_geometry(i)) {
            let lookup = shadow_lookup(
                frame,
                s,
                Vec4::from(g.position[i]).truncate(),
                Vec4::from(g.normal[i]).truncate(),
            );
            if lookup.kind == LOOKUP_COMPARE && lookup.depth_limit > 0.0 {
                let t = [
                    lookup.texel[0] as u32 * CULL_TILES / frame.map_size,
                    lookup.texel[1] as u32 * CULL_TILES / frame.map_size,
                ];
                let word = &mut tiles[z * words + (t[1] * CULL_TILES + t[0]) as usize];
                *word = (*word).max(lookup.depth_limit.to_bits());
            }
        }
    }
    tiles
}
