//! Twin of `kernels/shadow_test.wgsl`: ORs lit_k(p) of samples `ks` into the lattice masks.

use super::shadow::lit;
use crate::compute::buffers::MASK_WORDS;
use crate::layout::{GpuFrame, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use glam::Vec4;

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
        for (k, map) in &loaded {
            let bit = lit(frame, &samples[*k as usize], map, p, n);
            masks[base + (*k / 32) as usize] |= bit << (k % 32);
        }
    }
}
