//! Twin of `kernels/reproject_count.wgsl` `main`: packed comparison maps (byte = c + 1, 0 on
//! background) of every quad, from the lattice masks, and the word states that stand for a
//! uniform word's bytes in every quad's map.

use super::quad_corner;
use super::shadow_test::{SUMMARY_ANY_LIT, SUMMARY_ANY_UNLIT, SUMMARY_GEOMETRY, SUMMARY_WORD};
use crate::gpu::structs::GpuQuad;
use crate::render::gbuffer::GBufferCpu;
use crate::stages::adaptive_buffers::{MASK_WORDS, MIXED_WORD};

pub fn mask_bit(masks: &[u32], pixel: usize, k: u32) -> u32 {
    (masks[pixel * MASK_WORDS as usize + (k / 32) as usize] >> (k % 32)) & 1
}

/// c_q(p) of one quad at one pixel.
pub fn count(masks: &[u32], pixel: usize, q: &GpuQuad) -> u32 {
    (0..4)
        .map(|c| mask_bit(masks, pixel, quad_corner(q, c)))
        .sum()
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

/// Rows × words_per_row: a word's bytes when no geometry pixel in it has both a lit and an unlit
/// map (byte 5 all lit, 1 all unlit, 0 background), else MIXED_WORD. Read from the summary word
/// shadow_test keeps, as the kernel does.
pub fn word_state(masks: &[u32], width: u32, height: u32) -> Vec<u32> {
    let wpr = width.div_ceil(4);
    let mut out = vec![0u32; (height * wpr) as usize];
    for y in 0..height {
        for wx in 0..wpr {
            let mut state = 0u32;
            for b in 0..4 {
                let x = wx * 4 + b;
                if x >= width {
                    continue;
                }
                let summary = masks[(y * width + x) as usize * MASK_WORDS as usize + SUMMARY_WORD];
                if summary & SUMMARY_GEOMETRY == 0 {
                    continue;
                }
                let (lit, unlit) = (
                    summary & SUMMARY_ANY_LIT != 0,
                    summary & SUMMARY_ANY_UNLIT != 0,
                );
                if lit && unlit {
                    state = MIXED_WORD;
                    break;
                }
                state |= (if unlit { 1 } else { 5 }) << (b * 8);
            }
            out[(y * wpr + wx) as usize] = state;
        }
    }
    out
}
