//! Twin of `kernels/cull.wgsl`: the triangles each slot keeps, same operation order, and the
//! per-run bounds and normal cones the kernel reads.

use super::shadow::{shadow_compare, ShadowLookup, LOOKUP_COMPARE};
use crate::gpu::structs::{GpuFrame, GpuSample};
use crate::render::shadow_order::runs;
use crate::stages::adaptive_buffers::{CULL_TILES, CULL_TILE_WORDS};
use crate::stages::cull::CULL_RUN;
use glam::{Mat4, Vec2, Vec3, Vec4};

/// Texels of slack around projected bounds, stored-depth slack below their least depth, and the
/// most tiles scanned (CULL_MARGIN, CULL_DEPTH_SLACK and CULL_SCAN_TILES in the kernel, which
/// says why).
pub const CULL_MARGIN: f32 = 0.0625;
pub const CULL_DEPTH_SLACK: f32 = 1.525_878_9e-5;
pub const CULL_SCAN_TILES: u32 = 256;

/// Projected bounds: texel box, least stored depth, and whether a point lies at or behind the
/// sample's plane.
struct Bounds {
    lo: Vec2,
    hi: Vec2,
    z: f32,
    behind: bool,
}

impl Bounds {
    fn new() -> Self {
        Self {
            lo: Vec2::splat(3.0e38),
            hi: Vec2::splat(-3.0e38),
            z: 3.0e38,
            behind: false,
        }
    }

    fn add(&mut self, frame: &GpuFrame, m: &Mat4, p: Vec3) {
        let clip = *m * p.extend(1.0);
        if clip.w <= 0.0 {
            self.behind = true;
            return;
        }
        let size = frame.map_size as f32;
        let t = Vec2::new(
            (clip.x / clip.w * 0.5 + 0.5) * size,
            (0.5 - clip.y / clip.w * 0.5) * size,
        );
        self.lo = self.lo.min(t);
        self.hi = self.hi.max(t);
        self.z = self.z.min(clip.z / clip.w);
    }
}

/// Whether geometry within `b` can shadow a tested pixel: a texel centre near its box lies in a
/// tile of `tiles` (one sample's CULL_TILE_WORDS) whose largest tested limit its depth shadows.
fn reaches(frame: &GpuFrame, s: &GpuSample, tiles: &[u32], b: &Bounds) -> bool {
    if b.behind {
        return true;
    }
    let last = (frame.map_size - 1) as f32;
    let (a, c) = (
        (b.lo - CULL_MARGIN - 0.5).ceil(),
        (b.hi + CULL_MARGIN - 0.5).floor(),
    );
    if c.x < 0.0 || c.y < 0.0 || a.x > last || a.y > last || a.x > c.x || a.y > c.y {
        return false;
    }
    let tile = |v: f32| v.clamp(0.0, last) as u32 * CULL_TILES / frame.map_size;
    let (x0, x1, y0, y1) = (tile(a.x), tile(c.x), tile(a.y), tile(c.y));
    if (x1 - x0 + 1) * (y1 - y0 + 1) > CULL_SCAN_TILES {
        return true;
    }
    let z_lo = b.z - CULL_DEPTH_SLACK;
    for y in y0..=y1 {
        for x in x0..=x1 {
            let limit = tiles[(y * CULL_TILES + x) as usize];
            let nearest = ShadowLookup {
                texel: [0, 0],
                kind: LOOKUP_COMPARE,
                depth_limit: f32::from_bits(limit),
            };
            if limit != 0 && shadow_compare(s, &nearest, z_lo) == 0 {
                return true;
            }
        }
    }
    false
}

fn faces_away(eye: Vec3, lo: Vec4, hi: Vec4, axis: Vec4) -> bool {
    if axis.w != 1.0 {
        return false;
    }
    let centre = (lo.truncate() + hi.truncate()) * 0.5;
    let radius = (hi.truncate() - lo.truncate()).length() * 0.5;
    let v = centre - eye;
    let along = v.dot(axis.truncate());
    let across = (v.dot(v) - along * along).max(0.0).sqrt();
    along * lo.w - across * hi.w > radius * 1.01 + v.length() * 1e-3
}

/// `cull_face`: 0 the raster culls no face, 1 back faces, 2 front faces (GpuCull.cull_face).
fn run_keeps(
    frame: &GpuFrame,
    s: &GpuSample,
    tiles: &[u32],
    runs: &[[f32; 4]],
    r: usize,
    cull_face: u32,
) -> bool {
    let (lo, hi, mut axis) = (
        Vec4::from(runs[r * 3]),
        Vec4::from(runs[r * 3 + 1]),
        Vec4::from(runs[r * 3 + 2]),
    );
    if cull_face == 2 {
        axis = (-axis.truncate()).extend(axis.w);
    }
    if cull_face != 0
        && s.position[3] == 1.0
        && faces_away(Vec4::from(s.position).truncate(), lo, hi, axis)
    {
        return false;
    }
    let m = Mat4::from_cols_array_2d(&s.light_from_world);
    let mut b = Bounds::new();
    for c in 0..8u32 {
        b.add(
            frame,
            &m,
            Vec3::new(
                if c & 1 != 0 { hi.x } else { lo.x },
                if c & 2 != 0 { hi.y } else { lo.y },
                if c & 4 != 0 { hi.z } else { lo.z },
            ),
        );
    }
    reaches(frame, s, tiles, &b)
}

fn triangle_keeps(
    frame: &GpuFrame,
    s: &GpuSample,
    tiles: &[u32],
    positions: &[Vec3],
    indices: &[u32],
    t: usize,
) -> bool {
    let m = Mat4::from_cols_array_2d(&s.light_from_world);
    let mut b = Bounds::new();
    for j in 0..3 {
        b.add(frame, &m, positions[indices[t * 3 + j] as usize]);
    }
    reaches(frame, s, tiles, &b)
}

/// For each slot's lattice sample `ks[slot]`, the kept triangles (their places in `indices`, the
/// shadow raster's order) ascending: the kernel appends them in any order; the set is what must
/// match. `tiles` holds CULL_TILE_WORDS per lattice sample.
pub fn cull(
    frame: &GpuFrame,
    samples: &[GpuSample],
    tiles: &[u32],
    positions: &[Vec3],
    indices: &[u32],
    ks: &[u32],
    cull_face: u32,
) -> Vec<Vec<u32>> {
    let runs = runs(positions, indices);
    let (run, triangles) = (CULL_RUN as usize, indices.len() / 3);
    ks.iter()
        .map(|&k| {
            let words = CULL_TILE_WORDS as usize;
            let mine = &tiles[k as usize * words..(k as usize + 1) * words];
            let s = &samples[k as usize];
            (0..triangles.div_ceil(run))
                .filter(|&r| run_keeps(frame, s, mine, &runs, r, cull_face))
                .flat_map(|r| r * run..((r + 1) * run).min(triangles))
                .filter(|&t| triangle_keeps(frame, s, mine, positions, indices, t))
                .map(|t| t as u32)
                .collect()
        })
        .collect()
}
