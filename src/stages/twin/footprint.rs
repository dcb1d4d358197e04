//! Twin of `kernels/footprint.wgsl`: each slot's culling tiles from every geometry pixel (`main`)
//! or from the geometry pixels of listed 8 × 8 tiles (`listed`).

use super::shadow::{shadow_lookup, LOOKUP_COMPARE};
use crate::gpu::structs::{GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use crate::stages::adaptive_buffers::{CULL_TILES, CULL_TILE_WORDS};
use glam::Vec4;

/// CULL_TILE_WORDS words per sample of `samples` (slot n = samples[n]): 0 where no geometry pixel
/// of `g` looks up a texel, else the largest positive depth limit (f32 bits) tested there.
pub fn footprint(frame: &GpuFrame, samples: &[GpuSample], g: &GBufferCpu) -> Vec<u32> {
    raise(frame, samples, g, 0..g.position.len())
}

/// As [`footprint`], from the pixels of the 8 × 8 tiles `tiles` alone (tile t covers columns
/// (t mod ⌈width/8⌉)·8 .. +8 and rows (t div ⌈width/8⌉)·8 .. +8, cut at the frame's edge).
pub fn footprint_listed(
    frame: &GpuFrame,
    samples: &[GpuSample],
    g: &GBufferCpu,
    tiles: &[u32],
) -> Vec<u32> {
    let (w, h) = (g.width, g.height);
    let tiles_x = w.div_ceil(8);
    let pixels = tiles.iter().flat_map(move |&t| {
        let (x0, y0) = ((t % tiles_x) * 8, (t / tiles_x) * 8);
        (y0..(y0 + 8).min(h))
            .flat_map(move |y| (x0..(x0 + 8).min(w)).map(move |x| (y * w + x) as usize))
    });
    raise(frame, samples, g, pixels)
}

fn raise(
    frame: &GpuFrame,
    samples: &[GpuSample],
    g: &GBufferCpu,
    pixels: impl Iterator<Item = usize> + Clone,
) -> Vec<u32> {
    let words = CULL_TILE_WORDS as usize;
    let mut tiles = vec![0u32; samples.len() * words];
    for (z, s) in samples.iter().enumerate() {
        for i in pixels.clone().filter(|&i| g.is_geometry(i)) {
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
