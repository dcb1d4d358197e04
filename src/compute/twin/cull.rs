//! Twin of `kernels/cull.wgsl`: the triangles each slot keeps, same operation order.

use crate::compute::buffers::{CULL_TILES, CULL_TILE_WORDS};
use crate::compute::cull::TRIANGLES_PER_THREAD;
use crate::layout::{GpuFrame, GpuSample};
use glam::{Mat4, Vec2, Vec3, Vec4};

/// Texels of slack around a box (CULL_MARGIN in the kernel).
pub const CULL_MARGIN: f32 = 2.0;

fn texel_of(frame: &GpuFrame, m: &Mat4, p: Vec3) -> Vec3 {
    let clip = *m * Vec4::from((p, 1.0));
    let size = frame.map_size as f32;
    Vec3::new((clip.x / clip.w * 0.5 + 0.5) * size, (0.5 - clip.y / clip.w * 0.5) * size, clip.w)
}

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

/// World bounding box (min, max) of each run of TRIANGLES_PER_THREAD triangles (the kernel's
/// `bounds`).
pub fn bounds(positions: &[Vec3], indices: &[u32]) -> Vec<[f32; 4]> {
    indices
        .chunks(3 * TRIANGLES_PER_THREAD as usize)
        .flat_map(|run| {
            let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
            for &v in run {
                lo = lo.min(positions[v as usize]);
                hi = hi.max(positions[v as usize]);
            }
            [lo.extend(0.0).to_array(), hi.extend(0.0).to_array()]
        })
        .collect()
}

fn box_keeps(frame: &GpuFrame, m: &Mat4, tiles: &[u32], lo: Vec3, hi: Vec3) -> bool {
    let (mut a, mut b) = (Vec2::splat(3.0e38), Vec2::splat(-3.0e38));
    for c in 0..8u32 {
        let p = Vec3::new(if c & 1 != 0 { hi.x } else { lo.x }, if c & 2 != 0 { hi.y } else { lo.y }, if c & 4 != 0 { hi.z } else { lo.z });
        let t = texel_of(frame, m, p);
        if t.z <= 0.0 {
            return true;
        }
        a = a.min(Vec2::new(t.x, t.y));
        b = b.max(Vec2::new(t.x, t.y));
    }
    touches(frame, tiles, a, b)
}

fn triangle_keeps(frame: &GpuFrame, m: &Mat4, tiles: &[u32], positions: &[Vec3], indices: &[u32], t: usize) -> bool {
    let [a, b, c] = [0, 1, 2].map(|v| texel_of(frame, m, positions[indices[t * 3 + v] as usize]));
    if a.z <= 0.0 || b.z <= 0.0 || c.z <= 0.0 {
        return true;
    }
    let xy = |v: Vec3| Vec2::new(v.x, v.y);
    touches(frame, tiles, xy(a).min(xy(b)).min(xy(c)), xy(a).max(xy(b)).max(xy(c)))
}

/// For each slot's lattice sample `ks[slot]`, the kept triangle indices in ascending order (the
/// kernel appends in any order; the set is what must match). `tiles` holds CULL_TILE_WORDS per
/// lattice sample.
pub fn cull(frame: &GpuFrame, samples: &[GpuSample], tiles: &[u32], positions: &[Vec3], indices: &[u32], ks: &[u32]) -> Vec<Vec<u32>> {
    let boxes = bounds(positions, indices);
    let run = TRIANGLES_PER_THREAD as usize;
    let triangles = indices.len() / 3;
    ks.iter()
        .map(|&k| {
            let m = Mat4::from_cols_array_2d(&samples[k as usize].light_from_world);
            let words = CULL_TILE_WORDS as usize;
            let mine = &tiles[k as usize * words..(k as usize + 1) * words];
            let mut kept = Vec::new();
            for (r, first) in (0..triangles).step_by(run).enumerate() {
                let (lo, hi) = (Vec4::from(boxes[2 * r]).truncate(), Vec4::from(boxes[2 * r + 1]).truncate());
                if !box_keeps(frame, &m, mine, lo, hi) {
                    continue;
                }
                kept.extend((first..(first + run).min(triangles)).filter(|&t| triangle_keeps(frame, &m, mine, positions, indices, t)).map(|t| t as u32));
            }
            kept
        })
        .collect()
}
