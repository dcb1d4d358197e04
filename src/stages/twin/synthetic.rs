//! Synthetic inputs that drive the adaptive count stages alone (tests and benches), without a
//! scene or a frame: the lattice masks of two soft shadow edges that move with the light sample,
//! so the comparison maps hold every count, uniform regions and background; and quads, their
//! splits and children.

use super::shadow_test::{SUMMARY_ANY_LIT, SUMMARY_ANY_UNLIT, SUMMARY_GEOMETRY, SUMMARY_WORD};
use crate::gpu::structs::GpuQuad;
use crate::render::gbuffer::GBufferCpu;
use crate::stages::adaptive_buffers::{LATTICE_POINTS, LATTICE_SIDE, MASK_WORDS, NO_SPLIT};

/// Per pixel MASK_WORDS words as shadow_test leaves them once every lattice sample is tested.
pub struct EdgeMasks {
    pub width: u32,
    pub height: u32,
    pub masks: Vec<u32>,
    pub geometry: Vec<bool>,
}

/// `seed` moves the edges and the background hole.
pub fn edge_masks(width: u32, height: u32, seed: u64) -> EdgeMasks {
    let s = (seed % 97) as f32 / 97.0;
    let (hole_x, hole_y, hole_r) = (0.2 + 0.6 * s, 0.7 - 0.4 * s, 0.12);
    let mut masks = vec![0u32; (width * height * MASK_WORDS) as usize];
    let mut geometry = vec![false; (width * height) as usize];
    for y in 0..height {
        for x in 0..width {
            let (u, v) = (
                (x as f32 + 0.5) / width as f32,
                (y as f32 + 0.5) / height as f32,
            );
            let p = (y * width + x) as usize;
            if (u - hole_x).powi(2) + (v - hole_y).powi(2) < hole_r * hole_r {
                continue;
            }
            geometry[p] = true;
            let mut summary = SUMMARY_GEOMETRY;
            for k in 0..LATTICE_POINTS {
                let (i, j) = (
                    (k % LATTICE_SIDE) as f32 / 16.0 - 0.5,
                    (k / LATTICE_SIDE) as f32 / 16.0 - 0.5,
                );
                let first = u + 0.35 * v - 0.45 - 0.2 * s + 0.3 * i;
                let second = v - 0.5 * u - 0.25 + 0.25 * j;
                let lit = first < 0.0 || second > 0.15;
                if lit {
                    masks[p * MASK_WORDS as usize + (k / 32) as usize] |= 1 << (k % 32);
                }
                summary |= if lit {
                    SUMMARY_ANY_LIT
                } else {
                    SUMMARY_ANY_UNLIT
                };
            }
            masks[p * MASK_WORDS as usize + SUMMARY_WORD] |= summary;
        }
    }
    EdgeMasks {
        width,
        height,
        masks,
        geometry,
    }
}

impl EdgeMasks {
    /// A G-buffer whose geometry pixels are the masks' (the twins read only that of it).
    pub fn gbuffer(&self) -> GBufferCpu {
        let position = self
            .geometry
            .iter()
            .map(|&g| [0.0, 0.0, 0.0, g as u32 as f32])
            .collect();
        let normal = vec![[0.0, 0.0, 1.0, 0.0]; self.geometry.len()];
        GBufferCpu {
            width: self.width,
            height: self.height,
            position,
            normal: normal.clone(),
            shading_normal: normal,
        }
    }
}

/// Every quad of level `level` (size 16 >> level), in row order, each its parent's index in the
/// level above.
pub fn level_quads(level: u32) -> Vec<GpuQuad> {
    let size = 16 >> level;
    let side = 1u32 << level;
    (0..side * side)
        .map(|n| {
            let (qi, qj) = (n % side, n / side);
            let parent = if level == 0 {
                u32::MAX
            } else {
                (qj / 2) * (side / 2) + qi / 2
            };
            GpuQuad {
                i: qi * size,
                j: qj * size,
                size,
                parent,
            }
        })
        .collect()
}

/// The quads `split` picks split, the others not: each quad's first child index (NO_SPLIT where
/// it does not split) and the children, the four of split quad r at 4r..4r+3 with the first at
/// its origin (which probe's `probe_point` reads).
pub fn split(quads: &[GpuQuad], mut split: impl FnMut(usize) -> bool) -> (Vec<u32>, Vec<GpuQuad>) {
    let mut split_base = vec![NO_SPLIT; quads.len()];
    let mut children = Vec::new();
    for (q, quad) in quads.iter().enumerate() {
        if split(q) {
            split_base[q] = children.len() as u32;
            let s = quad.size / 2;
            children.extend((0..4).map(|c| GpuQuad {
                i: quad.i + (c & 1) * s,
                j: quad.j + (c >> 1) * s,
                size: s,
                parent: q as u32,
            }));
        }
    }
    (split_base, children)
}
