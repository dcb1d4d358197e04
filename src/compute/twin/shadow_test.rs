//! Twin of `kernels/shadow_test.wgsl`: ORs lit_k(p) of samples `ks` into the lattice masks.

use super::shadow::lit;
use crate::compute::buffers::MASK_WORDS;
use crate::layout::{GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use glam::Vec4;

/// Word 9's top bits summarise the pixel over every map tested so far (see common.wgsl).
pub const SUMMARY_WORD: usize = 9;
pub const SUMMARY_GEOMETRY: u32 = 0x8000_0000;
pub const SUMMARY_ANY_LIT: u32 = 0x4000_0000;
pub const SUMMARY_ANY_UNLIT: u32 = 0x2000_0000;

/// `samples` and `maps` are indexed by lattice index (maps only needed for `ks`).
pub fn shadow_test(frame: &GpuFrame, samples: &[GpuSample], maps: &dyn Fn(u32) -> Vec<f32>, g: &GBufferCpu, ks: &[u32], masks: &mut [u32]) {
    let loaded: Vec<(u32, Vec<f32>)> = ks.iter().map(|&k| (k, maps(k))).collect();
    for index in 0..g.position.len() {
        if !g.is_geometry(index) {
            continue;
        }
        let p = Vec4::from(g.position[index]).truncate();
        let n = Vec4::from(g.normal[index]).truncate();
        let base = index * MASK_WORDS as usize;
        let mut summary = SUMMARY_GEOMETRY;
        for (k, map) in &loaded {
            let bit = lit(frame, &samples[*k as usize], map, p, n);
            masks[base + (*k / 32) as usize] |= bit << (k % 32);
            summary |= if bit == 1 { SUMMARY_ANY_LIT } else { SUMMARY_ANY_UNLIT };
        }
        masks[base + SUMMARY_WORD] |= summary;
    }
}
