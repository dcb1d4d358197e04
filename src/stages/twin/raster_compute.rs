//! Twin of `kernels/raster_compute.wgsl`: the same projection, snap, edge values and depth, in the
//! same f32 operations and order (Rust never fuses a product into an add; the kernel fences its
//! products so that no compiler can). Edge values are native i64 here, two-word integers there.
//! Texels are visited in any order: each texel's word is the least over the triangles covering it.

use crate::gpu::structs::GpuSample;
use crate::scene::CullMode;
pub use crate::stages::raster_compute::FAR;

pub const RASTER_SUBTEXEL_BITS: u32 = 8;
pub const RASTER_COORD_LIMIT: f32 = 8_388_608.0;
pub const RASTER_SMALL_SIDE: i32 = 4;
pub const RASTER_LARGE_TILE: i32 = 8;

/// A triangle set up for one map, as `Tri` in the kernel: snapped vertices with positive area
/// (texel space, y down), their depths, its texel box (inclusive), 1 / area, and whether it was a
/// front face (counter-clockwise in NDC).
#[derive(Clone, Copy, Debug)]
pub struct Tri {
    pub v: [[i32; 2]; 3],
    pub z: [f32; 3],
    pub lo: [i32; 2],
    pub hi: [i32; 2],
    pub inv_area: f32,
    pub front: bool,
}

/// m · (p, 1), column-major, each row's products summed left to right.
pub fn project(m: &[[f32; 4]; 4], p: [f32; 3]) -> [f32; 4] {
    std::array::from_fn(|r| ((m[0][r] * p[0] + m[1][r] * p[1]) + m[2][r] * p[2]) + m[3][r])
}

/// A vertex snapped to 1/256 texel (x right, y down) with its depth z/w; None when it is at or
/// behind the sample's plane or beyond RASTER_COORD_LIMIT.
// The negated comparisons drop a NaN too, as the kernel's do.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn snap(s: &GpuSample, map_size: u32, p: [f32; 3]) -> Option<([i32; 2], f32)> {
    let c = project(&s.light_from_world, p);
    if !(c[3] > 0.0) {
        return None;
    }
    let scale = map_size as f32 * 128.0;
    let rw = 1.0 / c[3];
    let f = [((c[0] + c[3]) * rw) * scale, ((c[3] - c[1]) * rw) * scale];
    if !(f[0].abs() <= RASTER_COORD_LIMIT && f[1].abs() <= RASTER_COORD_LIMIT) {
        return None;
    }
    Some((
        [f[0].round_ties_even() as i32, f[1].round_ties_even() as i32],
        c[2] * rw,
    ))
}

/// The nearest f32 as the kernel's `wide_f32` computes it: the high word, scaled, plus the low word.
pub fn wide_f32(e: i64) -> f32 {
    ((e >> 32) as i32 as f32) * 4_294_967_296.0 + (e as u32 as f32)
}

/// The whole map as a job rectangle [first_x, first_y, last_x, last_y].
pub fn whole(map_size: u32) -> [i32; 4] {
    let last = map_size as i32 - 1;
    [0, 0, last, last]
}

/// `rect`: the job's texel rectangle [first_x, first_y, last_x, last_y] (inclusive).
/// `cull_face` 0: no face skipped; 1: back faces; 2: front faces (`stages::cull::cull_face`).
pub fn setup_snapped(v: [[i32; 2]; 3], z: [f32; 3], rect: [i32; 4], cull_face: u32) -> Option<Tri> {
    let lo: [i32; 2] = std::array::from_fn(|k| {
        ((v[0][k].min(v[1][k]).min(v[2][k]) + 127) >> RASTER_SUBTEXEL_BITS).max(rect[k])
    });
    let hi: [i32; 2] = std::array::from_fn(|k| {
        ((v[0][k].max(v[1][k]).max(v[2][k]) - 128) >> RASTER_SUBTEXEL_BITS).min(rect[2 + k])
    });
    if lo[0] > hi[0] || lo[1] > hi[1] {
        return None;
    }
    let area = (v[1][0] - v[0][0]) as i64 * (v[2][1] - v[0][1]) as i64
        - (v[1][1] - v[0][1]) as i64 * (v[2][0] - v[0][0]) as i64;
    let front = area < 0;
    if area == 0 || (cull_face == 1 && !front) || (cull_face == 2 && front) {
        return None;
    }
    let (v, z) = if front {
        ([v[0], v[2], v[1]], [z[0], z[2], z[1]])
    } else {
        (v, z)
    };
    Some(Tri {
        v,
        z,
        lo,
        hi,
        inv_area: 1.0 / wide_f32(area.abs()),
        front,
    })
}

/// Triangle `t` of `indices` over `positions` set up for sample `s` inside `rect`.
pub fn setup(
    s: &GpuSample,
    map_size: u32,
    rect: [i32; 4],
    cull_face: u32,
    positions: &[[f32; 3]],
    indices: &[u32],
    t: usize,
) -> Option<Tri> {
    let mut v = [[0; 2]; 3];
    let mut z = [0.0; 3];
    for j in 0..3 {
        (v[j], z[j]) = snap(s, map_size, positions[indices[t * 3 + j] as usize])?;
    }
    setup_snapped(v, z, rect, cull_face)
}

/// Edge a → b at point p (1/256 texels), and whether it is a top or left edge.
fn edge(a: [i32; 2], b: [i32; 2], p: [i64; 2]) -> (i64, bool) {
    let d = [(b[0] - a[0]) as i64, (b[1] - a[1]) as i64];
    let e = d[0] * (p[1] - a[1] as i64) - d[1] * (p[0] - a[0] as i64);
    (e, d[1] < 0 || (d[1] == 0 && d[0] > 0))
}

/// The depth of texel (x, y) when the triangle covers its centre (before the [0, 1) test).
pub fn texel(tri: &Tri, x: i32, y: i32) -> Option<f32> {
    let p = [x as i64 * 256 + 128, y as i64 * 256 + 128];
    let [a, b, c] = [
        edge(tri.v[1], tri.v[2], p),
        edge(tri.v[2], tri.v[0], p),
        edge(tri.v[0], tri.v[1], p),
    ];
    let covers = |(e, top_left): (i64, bool)| e > 0 || (e == 0 && top_left);
    if !(covers(a) && covers(b) && covers(c)) {
        return None;
    }
    let sum = wide_f32(a.0) * tri.z[0] + wide_f32(b.0) * tri.z[1];
    Some((sum + wide_f32(c.0) * tri.z[2]) * tri.inv_area)
}

/// Calls `f(x, y, depth)` for every texel of the triangle's box it covers.
pub fn for_each_texel(tri: &Tri, mut f: impl FnMut(i32, i32, f32)) {
    for y in tri.lo[1]..=tri.hi[1] {
        for x in tri.lo[0]..=tri.hi[0] {
            if let Some(d) = texel(tri, x, y) {
                f(x, y, d);
            }
        }
    }
}

/// One map's words, as `raster_compute` writes them: row-major, FAR where nothing is nearer.
pub fn rasterize(
    positions: &[[f32; 3]],
    indices: &[u32],
    s: &GpuSample,
    map_size: u32,
    cull: CullMode,
) -> Vec<u32> {
    rasterize_in(positions, indices, s, map_size, whole(map_size), cull)
}

/// [`rasterize`] inside a job's rectangle: texels outside keep FAR.
pub fn rasterize_in(
    positions: &[[f32; 3]],
    indices: &[u32],
    s: &GpuSample,
    map_size: u32,
    rect: [i32; 4],
    cull: CullMode,
) -> Vec<u32> {
    let n = map_size as usize;
    let mut words = vec![FAR; n * n];
    let cull_face = crate::stages::cull::cull_face(cull);
    for t in 0..indices.len() / 3 {
        if let Some(tri) = setup(s, map_size, rect, cull_face, positions, indices, t) {
            for_each_texel(&tri, |x, y, d| {
                if (0.0..1.0).contains(&d) {
                    let w = &mut words[y as usize * n + x as usize];
                    *w = (*w).min(d.to_bits() & 0x7fff_ffff);
                }
            });
        }
    }
    words
}

/// Hits per texel, counting every face (no cull): (front faces, back faces).
pub fn face_hits(
    positions: &[[f32; 3]],
    indices: &[u32],
    s: &GpuSample,
    map_size: u32,
) -> (Vec<u32>, Vec<u32>) {
    let n = map_size as usize;
    let (mut front, mut back) = (vec![0; n * n], vec![0; n * n]);
    for t in 0..indices.len() / 3 {
        if let Some(tri) = setup(s, map_size, whole(map_size), 0, positions, indices, t) {
            let counts = if tri.front { &mut front } else { &mut back };
            for_each_texel(&tri, |x, y, _| counts[y as usize * n + x as usize] += 1);
        }
    }
    (front, back)
}

/// `requested`: a chain's jobs (whole maps) for requests `first ..` of a level's list of `count`
/// (at most `capacity`), and its output words [maps, clear x y z, main x y z, store x y z].
pub fn requested(
    count: u32,
    list: &[u32],
    first: u32,
    capacity: u32,
    map_size: u32,
    triangles: u32,
) -> (Vec<crate::gpu::structs::GpuRasterJob>, [u32; 10]) {
    let maps = count.saturating_sub(first).min(capacity);
    let jobs = (first..first + maps)
        .map(|r| crate::gpu::structs::GpuRasterJob::whole(list[r as usize], map_size))
        .collect();
    let rows = |n: u32, y: u32| {
        let x = n.clamp(1, 32768);
        [x, y, n.div_ceil(x)]
    };
    let words = maps * map_size * map_size;
    let run = 64 * crate::stages::raster_compute::CLEAR_RUN;
    let mut out = [0; 10];
    out[0] = maps;
    out[1..4].copy_from_slice(&rows(words.div_ceil(run), 1));
    // `main_maps`: a triangle per invocation over every requested map, nothing when none is.
    out[4..7].copy_from_slice(&rows(if maps > 0 { triangles.div_ceil(64) } else { 0 }, 1));
    out[7..10].copy_from_slice(&rows((map_size * map_size).div_ceil(64), maps));
    (jobs, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fan of triangles around a texel centre whose edges run through texel centres (ties on
    /// every edge): each texel of the fan's square is covered exactly once.
    #[test]
    fn a_fan_with_edges_through_texel_centres_covers_each_texel_once() {
        let c = |x: i32, y: i32| [x * 256 + 128, y * 256 + 128];
        let centre = c(8, 8);
        let ring = [
            c(2, 2),
            c(8, 2),
            c(14, 2),
            c(14, 8),
            c(14, 14),
            c(8, 14),
            c(2, 14),
            c(2, 8),
        ];
        let mut counts = vec![0u32; 32 * 32];
        for k in 0..ring.len() {
            // Alternate the winding: the rule must not depend on the face's orientation.
            let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
            let v = if k % 2 == 0 {
                [centre, a, b]
            } else {
                [centre, b, a]
            };
            let tri =
                setup_snapped(v, [0.5; 3], whole(32), 0).expect("a fan triangle covers texels");
            for_each_texel(&tri, |x, y, d| {
                assert_eq!(d, 0.5, "a flat triangle's plane is flat");
                counts[y as usize * 32 + x as usize] += 1;
            });
        }
        for y in 0..32 {
            for x in 0..32 {
                // The square's own outline is covered where the top-left rule keeps it: its top
                // and left sides, not its right and bottom ones; the centre once.
                let want = u32::from((2..14).contains(&x) && (2..14).contains(&y));
                assert_eq!(counts[y * 32 + x], want, "texel ({x}, {y})");
            }
        }
    }
}
