//! Twin of `kernels/cull.wgsl`: the triangles each slot keeps, same operation order.

use crate::layout::{GpuFrame, GpuSample};
use glam::{Mat4, Vec2, Vec3, Vec4};

/// Texels of slack around the rectangle (CULL_MARGIN in the kernel).
pub const CULL_MARGIN: f32 = 2.0;

fn texel_of(frame: &GpuFrame, m: &Mat4, p: Vec3) -> Vec3 {
    let clip = *m * Vec4::from((p, 1.0));
    let size = frame.map_size as f32;
    Vec3::new((clip.x / clip.w * 0.5 + 0.5) * size, (0.5 - clip.y / clip.w * 0.5) * size, clip.w)
}

/// Whether triangle `t` can reach rectangle `r` ([min x, min y, max x, max y], inclusive texels).
pub fn keeps(frame: &GpuFrame, s: &GpuSample, r: [u32; 4], positions: &[Vec3], indices: &[u32], t: usize) -> bool {
    if r[0] > r[2] || r[1] > r[3] {
        return false;
    }
    let m = Mat4::from_cols_array_2d(&s.light_from_world);
    let [a, b, c] = [0, 1, 2].map(|v| texel_of(frame, &m, positions[indices[t * 3 + v] as usize]));
    if a.z <= 0.0 || b.z <= 0.0 || c.z <= 0.0 {
        return true;
    }
    let lo = Vec2::new(a.x, a.y).min(Vec2::new(b.x, b.y)).min(Vec2::new(c.x, c.y));
    let hi = Vec2::new(a.x, a.y).max(Vec2::new(b.x, b.y)).max(Vec2::new(c.x, c.y));
    hi.x >= r[0] as f32 - CULL_MARGIN
        && lo.x <= r[2] as f32 + 1.0 + CULL_MARGIN
        && hi.y >= r[1] as f32 - CULL_MARGIN
        && lo.y <= r[3] as f32 + 1.0 + CULL_MARGIN
}

/// For each slot's lattice sample `ks[slot]`, the kept triangle indices in ascending order
/// (the kernel appends in any order; the set is what must match).
pub fn cull(frame: &GpuFrame, samples: &[GpuSample], rects: &[[u32; 4]], positions: &[Vec3], indices: &[u32], ks: &[u32]) -> Vec<Vec<u32>> {
    ks.iter()
        .map(|&k| {
            let (s, r) = (&samples[k as usize], rects[k as usize]);
            (0..indices.len() / 3).filter(|&t| keeps(frame, s, r, positions, indices, t)).map(|t| t as u32).collect()
        })
        .collect()
}
