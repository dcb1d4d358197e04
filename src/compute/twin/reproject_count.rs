//! Twin of `kernels/reproject_count.wgsl` `main`: packed comparison maps (byte = c + 1, 0 on
//! background) of every quad, from the lattice masks.

use super::quad_corner;
use crate::compute::buffers::MASK_WORDS;
use crate::layout::GpuQuad;
use crate::render::gbuffer::GBufferCpu;

pub fn mask_bit(masks: &[u32], pixel: usize, k: u32) -> u32 {
    (masks[pixel * MASK_WORDS as usize + (k / 32) as usize] >> (k % 32)) & 1
}

/// c_q(p) of one quad at one pixel.
pub fn count(masks: &[u32], pixel: usize, q: &GpuQuad) -> u32 {
    (0..4).map(|c| mask_bit(masks, pixel, quad_corner(q, c))).sum()
}

/// Quads × rows × words_per_row packed words, as the kernel writes them.
pub fn reproject_count(quads: &[GpuQuad], masks: &[u32], g: &GBufferCpu) -> Vec<u32> {
    let (w, h) = (g.width, g.height);
    let wpr = w.div_ceil(4);
    let mut out = vec![0u32; quads.len() * (h * wpr) as usize];
    for (qi, q) in quads.iter().enumerate() {
        for y in 0..h {
            for wx in 0..wpr {
                let mut packed = 0u32;
                for b in 0..4 {
                    let x = wx * 4 + b;
                    if x < w {
                        let p = (y * w + x) as usize;
                        if g.is_geometry(p) {
                            packed |= (count(masks, p, q) + 1) << (b * 8);
                        }
                    }
                }
                out[qi * (h * wpr) as usize + (y * wpr + wx) as usize] = packed;
            }
        }
    }
    out
}
