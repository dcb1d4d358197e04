//! Twin of the whole scope = local pipeline (shadow_test `probes`, probe, shadow_test `list`,
//! reproject_count `list`, neighbourhood `list`, quad_count, subdivide, compact; at the last level
//! reproject_count `last`): per-pixel adaptive quadrature in exact integers.

use super::neighbourhood::{low_quality, Screen};
use super::quad_corner;
use super::shadow_test::{LocalTest, Maps};
use super::subdivide::{subdivide, SplitLevel, SplitRule};
use crate::gpu::structs::{GpuFrame, GpuQuad, GpuSample};
use crate::render::gbuffer::GBufferCpu;
use crate::stages::adaptive_buffers::{LATTICE_POINTS, MASK_WORDS};

#[derive(Debug, Default)]
pub struct LocalOut {
    /// Σ c · 4^(max_level − level) per pixel; V = value / (4 · 4^max_level).
    pub visibility_fixed: Vec<u32>,
    /// Per level: items evaluated, quads (sorted), low-quality count per quad (in quad order), new samples.
    pub items: Vec<u32>,
    /// Per level: probes compact appended for the next level.
    pub probes: Vec<u32>,
    pub quads: Vec<Vec<GpuQuad>>,
    pub new_samples: Vec<Vec<u32>>,
    /// Per level: shadow-map lookups (shadow_test `probes` and `list`).
    pub lookups: Vec<u32>,
    /// Per level, after it: the consulted samples and the lattice masks of every pixel.
    pub consulted: Vec<Vec<u32>>,
    pub masks: Vec<Vec<u32>>,
}

/// `rule(level)` is the split rule subdivide applies at each level.
pub fn local(
    frame: &GpuFrame,
    samples: &[GpuSample],
    maps: &dyn Fn(u32) -> Vec<f32>,
    g: &GBufferCpu,
    max_level: u32,
    rule: &dyn Fn(u32) -> SplitRule,
) -> LocalOut {
    let s = Screen {
        width: g.width,
        height: g.height,
    };
    let wpr = s.words_per_row();
    let words = (s.height * wpr) as usize;
    let mask_words = g.position.len() * MASK_WORDS as usize;
    let mut test = LocalTest {
        frame,
        samples,
        g,
        maps: Maps::new(maps),
        consulted: vec![0; mask_words],
        masks: vec![0; mask_words],
    };
    let mut out = LocalOut {
        visibility_fixed: vec![0; g.position.len()],
        ..Default::default()
    };
    let mut items: Vec<(u32, u32)> = (0..g.position.len() as u32)
        .filter(|&p| g.is_geometry(p as usize))
        .map(|p| (p, 0))
        .collect();
    let mut quads = vec![GpuQuad {
        i: 0,
        j: 0,
        size: 16,
        parent: u32::MAX,
    }];
    let mut state = vec![0u32; LATTICE_POINTS as usize];
    for k in [0, 16, 272, 288] {
        state[k] = 1;
    }
    let mut sample_level = vec![0u32; LATTICE_POINTS as usize];
    let geometry = items.len() as u32;
    // (pixel, first child, lit): uniform pixels of last level's split quads (probe.wgsl).
    let mut probes: Vec<(u32, u32, bool)> = Vec::new();
    for level in 0..=max_level {
        let probe_items: Vec<(u32, u32)> = probes.iter().map(|&(p, base, _)| (p, base)).collect();
        let mut lookups = test.probes(&quads, &probe_items);
        super::probe::probe(
            &probes,
            &quads,
            &test.masks,
            level,
            max_level,
            &mut items,
            &mut out.visibility_fixed,
        );
        lookups += test.list(&quads, &items);
        if level == max_level {
            // reproject_count `last`: nothing splits, so each item adds its count to V at once.
            for &(p, q) in &items {
                let c: u32 = (0..4)
                    .map(|corner| test.bit(p, quad_corner(&quads[q as usize], corner)))
                    .sum();
                out.visibility_fixed[p as usize] += c;
            }
            out.push_level(&items, 0, &quads, Vec::new(), lookups, &test);
            break;
        }
        let mut counts = vec![0u32; quads.len() * words];
        for &(p, q) in &items {
            let c: u32 = (0..4)
                .map(|corner| test.bit(p, quad_corner(&quads[q as usize], corner)))
                .sum();
            let (x, y) = (p % s.width, p / s.width);
            counts[q as usize * words + (y * wpr + x / 4) as usize] |= (c + 1) << ((x & 3) * 8);
        }
        let mut counters = vec![0u32; quads.len()];
        for &(p, q) in &items {
            let (x, y) = ((p % s.width) as i32, (p / s.width) as i32);
            counters[q as usize] += low_quality(&counts, &s, q as usize, x, y) as u32;
        }
        let at = SplitLevel {
            level,
            max_level,
            rule: rule(level),
            geometry_pixels: geometry,
        };
        let sub = subdivide(&at, &quads, &counters, &mut state, &mut sample_level);
        let next = super::compact::compact(
            &s,
            level,
            max_level,
            &items,
            &counts,
            &sub.split_base,
            &mut out.visibility_fixed,
        );
        out.push_level(
            &items,
            next.probes.len() as u32,
            &quads,
            sub.new_samples.clone(),
            lookups,
            &test,
        );
        probes = next.probes;
        items = next.next_items;
        quads = sub.next_quads;
        if quads.is_empty() {
            break;
        }
    }
    out
}

impl LocalOut {
    /// One level's record, after it.
    fn push_level(
        &mut self,
        items: &[(u32, u32)],
        probes: u32,
        quads: &[GpuQuad],
        new_samples: Vec<u32>,
        lookups: u32,
        test: &LocalTest,
    ) {
        self.items.push(items.len() as u32);
        self.probes.push(probes);
        let mut sorted = quads.to_vec();
        sorted.iter_mut().for_each(|q| q.parent = 0);
        sorted.sort();
        self.quads.push(sorted);
        self.new_samples.push(new_samples);
        self.lookups.push(lookups);
        self.consulted.push(test.consulted.clone());
        self.masks.push(test.masks.clone());
    }
}
