//! Twin of probe.wgsl `main`: each probe (a uniform pixel of a split quad) reads the parent's five
//! new samples' lit bits; a disagreement makes the pixel four child items, an agreement that is lit
//! adds the parent's uniform share to V's integer sum.

use super::probe_point;
use crate::gpu::structs::GpuQuad;
use crate::stages::adaptive_buffers::MASK_WORDS;

/// A probe's second word: its parent's first child | PROBE_LIT when the parent's corners are all
/// lit (common.wgsl PROBE_LIT).
pub const PROBE_LIT: u32 = 0x8000_0000;

/// `probes`: (pixel, first child in `quads`, lit). Appends the expanded items to `items` in probe
/// order (the GPU appends them in any order) and adds the lit shares to `visibility_fixed`.
pub fn probe(
    probes: &[(u32, u32, bool)],
    quads: &[GpuQuad],
    masks: &[u32],
    level: u32,
    max_level: u32,
    items: &mut Vec<(u32, u32)>,
    visibility_fixed: &mut [u32],
) {
    let bit = |p: u32, k: u32| (masks[(p * MASK_WORDS + k / 32) as usize] >> (k % 32)) & 1 == 1;
    for &(p, base, lit) in probes {
        let q = quads[base as usize];
        if (0..5).any(|n| bit(p, probe_point(&q, n)) != lit) {
            items.extend((0..4).map(|child| (p, base + child)));
        } else if lit {
            visibility_fixed[p as usize] += 4 << (2 * (max_level - level + 1));
        }
    }
}
