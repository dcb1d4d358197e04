//! The shadow raster's triangle order: the mesh's triangles sorted by the Morton code of their
//! centroids, once per scene. Consecutive triangles are then neighbours in space, so the cull
//! pass's runs of consecutive triangles have small boxes and narrow normal cones. A depth-only raster
//! with a Less test keeps the nearest fragment whatever the draw order, so every shadow map is
//! the same texel for texel; the G-buffer keeps the scene's own order.

use glam::Vec3;

/// Bits per axis of the Morton code (63 bits in all).
const BITS: u32 = 21;

/// `indices` with its triangles reordered along the Morton curve of their centroids (ties keep the
/// scene's order, so the result depends only on the mesh).
pub fn shadow_order(positions: &[Vec3], indices: &[u32]) -> Vec<u32> {
    let centroids: Vec<Vec3> = indices
        .chunks_exact(3)
        .map(|t| {
            (positions[t[0] as usize] + positions[t[1] as usize] + positions[t[2] as usize]) / 3.0
        })
        .collect();
    let (lo, hi) = centroids.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), c| (lo.min(*c), hi.max(*c)),
    );
    let scale = ((1u32 << BITS) - 1) as f32 / (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
    let mut keyed: Vec<(u64, u32)> = centroids
        .iter()
        .enumerate()
        .map(|(t, c)| {
            let q = ((*c - lo) * scale)
                .round()
                .clamp(Vec3::ZERO, Vec3::splat(((1u32 << BITS) - 1) as f32));
            (
                spread(q.x as u32) | spread(q.y as u32) << 1 | spread(q.z as u32) << 2,
                t as u32,
            )
        })
        .collect();
    keyed.sort_unstable();
    keyed
        .iter()
        .flat_map(|&(_, t)| indices[t as usize * 3..t as usize * 3 + 3].iter().copied())
        .collect()
}

/// The low BITS bits of `v`, two zero bits after each.
fn spread(v: u32) -> u64 {
    let mut x = v as u64 & 0x1f_ffff;
    x = (x | x << 32) & 0x1f_0000_0000_ffff;
    x = (x | x << 16) & 0x1f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    x = (x | x << 2) & 0x1249_2492_4924_9249;
    x
}

/// Per run of CULL_RUN triangles, three vec4s: (box min, cos θ), (box max, sin θ), (cone axis,
/// 1 when every face normal (b−a)×(c−a) lies within θ < 90° of the axis, else 0). θ is widened a
/// little so the cone holds every normal despite rounding.
pub(crate) fn runs(positions: &[Vec3], indices: &[u32]) -> Vec<[f32; 4]> {
    indices
        .chunks(3 * crate::gpu::stages::CULL_RUN as usize)
        .flat_map(|run| {
            let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
            for &v in run {
                lo = lo.min(positions[v as usize]);
                hi = hi.max(positions[v as usize]);
            }
            let normals: Vec<Vec3> = run
                .chunks_exact(3)
                .map(|t| {
                    let [a, b, c] = [0, 1, 2].map(|i| positions[t[i] as usize]);
                    (b - a).cross(c - a).normalize_or_zero()
                })
                .collect();
            let sum: Vec3 = normals.iter().sum();
            let axis = sum.normalize_or_zero();
            let min_cos = normals
                .iter()
                .map(|n| if *n == Vec3::ZERO { -1.0 } else { n.dot(axis) })
                .fold(1.0f32, f32::min);
            // Widen by ~0.01 rad; a cone of 80° or more is not worth testing.
            let cos = (min_cos.clamp(-1.0, 1.0).acos() + 0.01).cos();
            let valid = axis != Vec3::ZERO && min_cos > 0.2;
            let sin = (1.0 - cos * cos).max(0.0).sqrt();
            [
                lo.extend(cos).to_array(),
                hi.extend(sin).to_array(),
                axis.extend(if valid { 1.0 } else { 0.0 }).to_array(),
            ]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_puts_two_zero_bits_after_each_bit() {
        assert_eq!(spread(0b1011), 0b001_000_001_001);
        assert_eq!(spread(0x1f_ffff), 0x1249_2492_4924_9249);
    }

    #[test]
    fn same_triangles_same_windings_neighbours_first() {
        // Four triangles along x, given far-near-far-near: the order follows the curve.
        let positions: Vec<Vec3> = (0..4)
            .flat_map(|i| {
                [
                    Vec3::new(i as f32 * 10.0, 0.0, 0.0),
                    Vec3::new(i as f32 * 10.0 + 1.0, 0.0, 0.0),
                    Vec3::new(i as f32 * 10.0, 1.0, 0.0),
                ]
            })
            .collect();
        let indices: Vec<u32> = [3u32, 0, 2, 1]
            .iter()
            .flat_map(|&t| [t * 3, t * 3 + 1, t * 3 + 2])
            .collect();
        let ordered = shadow_order(&positions, &indices);
        assert_eq!(ordered, (0..12).collect::<Vec<u32>>());
    }
}
