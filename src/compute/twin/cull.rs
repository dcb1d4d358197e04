//! Twin of `kernels/cull.wgsl`: the runs of triangles each slot keeps, same operation order, and
//! the per-run bounds and normal cones the kernel reads.

use crate::compute::buffers::{CULL_TILES, CULL_TILE_WORDS};
use crate::compute::cull::{runs, CULL_RUN};
use crate::layout::{GpuFrame, GpuSample};
use glam::{Mat4, Vec2, Vec3, Vec4};

/// Texels of slack around a box (CULL_MARGIN in the kernel).
pub const CULL_MARGIN: f32 = 2.0;

/// Whether the texel box [lo, hi], widened by CULL_MARGIN, touches a marked tile in `tiles`
/// (one sample's CULL_TILE_WORDS).
fn touches(frame: &GpuFrame, tiles: &[u32], lo: Vec2, hi: Vec2) -> bool {
    let size = frame.map_size as f32;
    let (a, b) = (lo - CULL_MARGIN, hi + CULL_MARGIN);
    if b.x < 0.0 || b.y < 0.0 || a.x >= size || a.y >= size {
        return false;
    }
    let tile = size / CULL_TILES as f32;
    let last = (CULL_TILES - 1) as f32;
    let t0 = (a / tile).floor().clamp(Vec2::ZERO, Vec2::splat(last));
    let t1 = (b / tile).floor().clamp(Vec2::ZERO, Vec2::splat(last));
    for y in t0.y as u32..=t1.y as u32 {
        for x in t0.x as u32..=t1.x as u32 {
            let bit = y * CULL_TILES + x;
            if (tiles[(bit / 32) as usize] >> (bit % 32)) & 1 == 1 {
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
fn run_keeps(frame: &GpuFrame, s: &GpuSample, tiles: &[u32], runs: &[[f32; 4]], r: usize, cull_face: u32) -> bool {
    let (lo, hi, mut axis) = (Vec4::from(runs[r * 3]), Vec4::from(runs[r * 3 + 1]), Vec4::from(runs[r * 3 + 2]));
    if cull_face == 2 {
        axis = (-axis.truncate()).extend(axis.w);
    }
    if cull_face != 0 && faces_away(Vec4::from(s.position).truncate(), lo, hi, axis) {
        return false;
    }
    let m = Mat4::from_cols_array_2d(&s.light_from_world);
    let size = frame.map_size as f32;
    let (mut a, mut b) = (Vec2::splat(3.0e38), Vec2::splat(-3.0e38));
    for c in 0..8u32 {
        let p = Vec3::new(if c & 1 != 0 { hi.x } else { lo.x }, if c & 2 != 0 { hi.y } else { lo.y }, if c & 4 != 0 { hi.z } else { lo.z });
        let clip = m * p.extend(1.0);
        if clip.w <= 0.0 {
            return true;
        }
        let t = Vec2::new((clip.x / clip.w * 0.5 + 0.5) * size, (0.5 - clip.y / clip.w * 0.5) * size);
        a = a.min(t);
        b = b.max(t);
    }
    touches(frame, tiles, a, b)
}

/// For each slot's lattice sample `ks[slot]`, the kept triangle indices in ascending order (the
/// kernel appends runs in any order; the set is what must match). `tiles` holds CULL_TILE_WORDS
/// per lattice sample.
pub fn cull(frame: &GpuFrame, samples: &[GpuSample], tiles: &[u32], positions: &[Vec3], indices: &[u32], ks: &[u32], cull_face: u32) -> Vec<Vec<u32>> {
    let runs = runs(positions, indices);
    let (run, triangles) = (CULL_RUN as usize, indices.len() / 3);
    ks.iter()
        .map(|&k| {
            let words = CULL_TILE_WORDS as usize;
            let mine = &tiles[k as usize * words..(k as usize + 1) * words];
            let s = &samples[k as usize];
            (0..triangles.div_ceil(run))
                .filter(|&r| run_keeps(frame, s, mine, &runs, r, cull_face))
                .flat_map(|r| (r * run..((r + 1) * run).min(triangles)).map(|t| t as u32))
                .collect()
        })
        .collect()
}
