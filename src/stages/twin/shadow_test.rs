//! Twin of `kernels/shadow_test.wgsl`: ORs lit_k(p) of samples `ks` into the lattice masks
//! (the block entry points; `fill_blocks`, which fills their blocks, has a twin of its own),
//! or of the samples each item and probe consults, once per (pixel, sample) (`list`, `probes`).

use super::shadow::{face_offset, lit};
use super::{probe_point, quad_corner};
use crate::gpu::structs::{GpuFrame, GpuQuad, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use crate::stages::adaptive_buffers::{LATTICE_POINTS, MASK_WORDS};
use crate::stages::shadow_test::{TEST_BLOCK, TEST_SLOTS, TEST_TAILS};
use glam::Vec4;

/// Word 9's top bits summarise the pixel over every map tested so far (see common.wgsl).
pub const SUMMARY_WORD: usize = 9;
pub const SUMMARY_GEOMETRY: u32 = 0x8000_0000;
pub const SUMMARY_ANY_LIT: u32 = 0x4000_0000;
pub const SUMMARY_ANY_UNLIT: u32 = 0x2000_0000;

/// `samples` and `maps` are indexed by lattice index (maps only needed for `ks`); a point light's
/// face f of lattice sample k is record (and map) k + 289 f.
pub fn shadow_test(
    frame: &GpuFrame,
    samples: &[GpuSample],
    maps: &dyn Fn(u32) -> Vec<f32>,
    g: &GBufferCpu,
    ks: &[u32],
    masks: &mut [u32],
) {
    let faces = |k: u32| {
        if samples[k as usize].cube_face != 0 {
            6
        } else {
            1
        }
    };
    let loaded: std::collections::HashMap<u32, Vec<f32>> = ks
        .iter()
        .flat_map(|&k| (0..faces(k)).map(move |f| k + LATTICE_POINTS * f))
        .map(|i| (i, maps(i)))
        .collect();
    for index in 0..g.position.len() {
        if !g.is_geometry(index) {
            continue;
        }
        let p = Vec4::from(g.position[index]).truncate();
        let n = Vec4::from(g.normal[index]).truncate();
        let base = index * MASK_WORDS as usize;
        let mut summary = SUMMARY_GEOMETRY;
        for k in ks {
            let i = *k as usize
                + LATTICE_POINTS as usize * face_offset(frame, &samples[*k as usize], p);
            let bit = lit(frame, &samples[i], &loaded[&(i as u32)], p, n);
            masks[base + (*k / 32) as usize] |= bit << (k % 32);
            summary |= if bit == 1 {
                SUMMARY_ANY_LIT
            } else {
                SUMMARY_ANY_UNLIT
            };
        }
        masks[base + SUMMARY_WORD] |= summary;
    }
}

/// Twin of `fill_blocks`: each block slot's lattice indices. The requested samples of `listed`
/// (state ≠ 0) keep the list's order: full blocks of TEST_BLOCK first, then the tails of the rest,
/// largest first, in the slots after the full blocks of a list of `bound`. Empty: not dispatched.
pub fn fill_blocks(listed: &[u32], state: &[u32], bound: u32) -> Vec<Vec<u32>> {
    let requested: Vec<u32> = listed
        .iter()
        .copied()
        .filter(|&k| state[k as usize] != 0)
        .collect();
    let mut slots = vec![Vec::new(); TEST_SLOTS as usize];
    let mut chunks = requested.chunks_exact(TEST_BLOCK as usize);
    for (s, block) in chunks.by_ref().enumerate() {
        slots[s] = block.to_vec();
    }
    let mut rest = chunks.remainder();
    for (n, &size) in TEST_TAILS.iter().enumerate() {
        if rest.len() as u32 & size != 0 {
            let (block, after) = rest.split_at(size as usize);
            slots[(bound / TEST_BLOCK) as usize + n] = block.to_vec();
            rest = after;
        }
    }
    slots
}

/// Each lattice sample's map, loaded on first use.
pub struct Maps<'a> {
    load: &'a dyn Fn(u32) -> Vec<f32>,
    cache: Vec<Option<Vec<f32>>>,
}

impl<'a> Maps<'a> {
    pub fn new(load: &'a dyn Fn(u32) -> Vec<f32>) -> Self {
        Self {
            load,
            cache: (0..LATTICE_POINTS).map(|_| None).collect(),
        }
    }
    fn get(&mut self, k: u32) -> &[f32] {
        let load = self.load;
        self.cache[k as usize].get_or_insert_with(|| load(k))
    }
}

/// What the local entry points read and write: the frame's per-pixel masks and the lookup count.
pub struct LocalTest<'a> {
    pub frame: &'a GpuFrame,
    pub samples: &'a [GpuSample],
    pub g: &'a GBufferCpu,
    pub maps: Maps<'a>,
    /// Bit k: the pixel consulted sample k (claimed).
    pub consulted: Vec<u32>,
    /// Bit k: sample k lights the pixel (claimed samples only).
    pub masks: Vec<u32>,
}

impl LocalTest<'_> {
    /// Twin of `list`: the four corners of each item (pixel, quad index); returns the lookups.
    pub fn list(&mut self, quads: &[GpuQuad], items: &[(u32, u32)]) -> u32 {
        items
            .iter()
            .map(|&(p, q)| {
                self.test_claimed(
                    p,
                    &(0..4)
                        .map(|c| quad_corner(&quads[q as usize], c))
                        .collect::<Vec<_>>(),
                )
            })
            .sum()
    }

    /// Twin of `probes`: the five new samples of each probe (pixel, first child); returns the lookups.
    pub fn probes(&mut self, quads: &[GpuQuad], probes: &[(u32, u32)]) -> u32 {
        probes
            .iter()
            .map(|&(p, base)| {
                self.test_claimed(
                    p,
                    &(0..5)
                        .map(|n| probe_point(&quads[base as usize], n))
                        .collect::<Vec<_>>(),
                )
            })
            .sum()
    }

    /// Claims `ks` for pixel p and tests those not claimed before.
    fn test_claimed(&mut self, p: u32, ks: &[u32]) -> u32 {
        let mut mine = 0u32;
        for (i, &k) in ks.iter().enumerate() {
            let (word, bit) = ((p * MASK_WORDS + k / 32) as usize, 1u32 << (k % 32));
            if self.consulted[word] & bit == 0 {
                mine |= 1 << i;
            }
            self.consulted[word] |= bit;
        }
        if mine == 0 {
            return 0;
        }
        let position = Vec4::from(self.g.position[p as usize]).truncate();
        let normal = Vec4::from(self.g.normal[p as usize]).truncate();
        for (i, &k) in ks.iter().enumerate() {
            if mine & (1 << i) == 0 {
                continue;
            }
            let (frame, samples) = (self.frame, self.samples);
            if lit(
                frame,
                &samples[k as usize],
                self.maps.get(k),
                position,
                normal,
            ) == 1
            {
                self.masks[(p * MASK_WORDS + k / 32) as usize] |= 1 << (k % 32);
            }
        }
        mine.count_ones()
    }

    /// Whether sample k lights pixel p, as the masks cached it.
    pub fn bit(&self, p: u32, k: u32) -> u32 {
        (self.masks[(p * MASK_WORDS + k / 32) as usize] >> (k % 32)) & 1
    }
}
