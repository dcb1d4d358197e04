//! The acceleration structure the environment rays traverse on the GPU (`env_trace`, `env_count`):
//! a binary BVH built on the CPU from the scene's triangles, stored flat (children side by side),
//! with a CPU traversal written operation for operation like the WGSL (the twins use it).
//!
//! Why a BVH and not the seed's linear octree: an octree cell holds every triangle that straddles
//! it, so a triangle is stored (and tested) once per cell it touches, and cells are cubes whatever
//! the geometry; a BVH holds each triangle once, in a box that fits it. Figures in
//! docs/environment.md.

use crate::gpu::structs::{GpuBvhNode, GpuTriangle};
use glam::Vec3;

/// Triangles per leaf at most.
pub(crate) const LEAF_SIZE: usize = 4;
/// Traversal stack depth in the kernels; the build stops splitting before it could overflow.
pub const STACK_DEPTH: usize = 32;

pub struct Bvh {
    pub(crate) nodes: Vec<GpuBvhNode>,
    pub(crate) triangles: Vec<GpuTriangle>,
    /// The input index of each entry of `triangles` (leaf order): truth_trace stores the vertices.
    pub(crate) source: Vec<u32>,
    pub(crate) depth: usize,
}

struct Item {
    lo: Vec3,
    hi: Vec3,
    centre: Vec3,
    index: usize,
}

impl Bvh {
    /// Binned SAH split (12 bins per axis), the median on the longest axis where no bin split
    /// separates the centroids; leaves of at most [`LEAF_SIZE`].
    pub(crate) fn build(triangles: &[[Vec3; 3]]) -> Bvh {
        let mut items: Vec<Item> = triangles
            .iter()
            .enumerate()
            .filter(|(_, t)| t.iter().all(|v| v.is_finite()))
            .map(|(index, t)| {
                let lo = t[0].min(t[1]).min(t[2]);
                let hi = t[0].max(t[1]).max(t[2]);
                Item {
                    lo,
                    hi,
                    centre: (lo + hi) * 0.5,
                    index,
                }
            })
            .collect();
        let mut bvh = Bvh {
            nodes: vec![GpuBvhNode::default()],
            triangles: Vec::with_capacity(items.len()),
            source: Vec::with_capacity(items.len()),
            depth: 1,
        };
        let n = items.len();
        bvh.split(0, &mut items[..], 1, triangles);
        debug_assert_eq!(bvh.triangles.len(), n);
        bvh
    }

    fn split(&mut self, node: usize, items: &mut [Item], depth: usize, tris: &[[Vec3; 3]]) {
        self.depth = self.depth.max(depth);
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let (mut clo, mut chi) = (lo, hi);
        for it in items.iter() {
            lo = lo.min(it.lo);
            hi = hi.max(it.hi);
            clo = clo.min(it.centre);
            chi = chi.max(it.centre);
        }
        if items.is_empty() {
            lo = Vec3::ZERO;
            hi = Vec3::ZERO;
        }
        let extent = chi - clo;
        // Stack: every level pushes at most one extra entry, so depth < STACK_DEPTH is safe.
        if items.len() <= LEAF_SIZE || depth + 1 >= STACK_DEPTH || extent.max_element() <= 0.0 {
            let first = self.triangles.len() as u32;
            for it in items.iter() {
                let t = tris[it.index];
                let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
                self.triangles.push(GpuTriangle {
                    v0: t[0].extend(0.0).to_array(),
                    e1: e1.extend(0.0).to_array(),
                    e2: e2.extend(0.0).to_array(),
                });
                self.source.push(it.index as u32);
            }
            self.nodes[node] = GpuBvhNode {
                min: lo.to_array(),
                left_first: first,
                max: hi.to_array(),
                count: items.len() as u32,
            };
            return;
        }
        let mid = match sah_split(items, clo, extent) {
            Some(m) => m,
            None => {
                // No binned split beats the leaf's cost estimate's shape: the median on the longest axis.
                let axis = if extent.x >= extent.y && extent.x >= extent.z {
                    0
                } else if extent.y >= extent.z {
                    1
                } else {
                    2
                };
                let mid = items.len() / 2;
                items.select_nth_unstable_by(mid, |a, b| a.centre[axis].total_cmp(&b.centre[axis]));
                mid
            }
        };
        let left = self.nodes.len();
        self.nodes.push(GpuBvhNode::default());
        self.nodes.push(GpuBvhNode::default());
        self.nodes[node] = GpuBvhNode {
            min: lo.to_array(),
            left_first: left as u32,
            max: hi.to_array(),
            count: 0,
        };
        let (a, b) = items.split_at_mut(mid);
        self.split(left, a, depth + 1, tris);
        self.split(left + 1, b, depth + 1, tris);
    }

    /// Any triangle at t ∈ (0, t_max) along origin + t·dir? The CPU twin of `env_occluded` in
    /// kernels/shared/environment.wgsl, operation for operation.
    // The twin of `env_occluded`: only the twins' tests call it.
    #[cfg(any(test, feature = "twins"))]
    pub(crate) fn occluded(&self, origin: [f32; 3], dir: [f32; 3], t_max: f32) -> bool {
        let inv = [1.0 / dir[0], 1.0 / dir[1], 1.0 / dir[2]];
        let mut stack = [0u32; STACK_DEPTH];
        let mut top = 1usize;
        stack[0] = 0;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top] as usize];
            if !slab(&node, origin, inv, t_max) {
                continue;
            }
            if node.count == 0 {
                stack[top] = node.left_first;
                stack[top + 1] = node.left_first + 1;
                top += 2;
                continue;
            }
            for k in node.left_first..node.left_first + node.count {
                if hit(&self.triangles[k as usize], origin, dir, t_max) {
                    return true;
                }
            }
        }
        false
    }
}

/// Binned surface-area heuristic: over 12 centroid bins per axis, the split with the least
/// Σ area(child) × triangles(child); items are partitioned in place and the left count returned.
fn sah_split(items: &mut [Item], clo: Vec3, extent: Vec3) -> Option<usize> {
    const BINS: usize = 12;
    let area = |lo: Vec3, hi: Vec3| {
        let d = (hi - lo).max(Vec3::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    };
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let bin_of =
            |c: f32| (((c - clo[axis]) / extent[axis] * BINS as f32) as usize).min(BINS - 1);
        let mut boxes = [(
            Vec3::splat(f32::INFINITY),
            Vec3::splat(f32::NEG_INFINITY),
            0usize,
        ); BINS];
        for it in items.iter() {
            let b = &mut boxes[bin_of(it.centre[axis])];
            b.0 = b.0.min(it.lo);
            b.1 = b.1.max(it.hi);
            b.2 += 1;
        }
        for cut in 1..BINS {
            let (mut l, mut r) = (
                (
                    Vec3::splat(f32::INFINITY),
                    Vec3::splat(f32::NEG_INFINITY),
                    0usize,
                ),
                (
                    Vec3::splat(f32::INFINITY),
                    Vec3::splat(f32::NEG_INFINITY),
                    0usize,
                ),
            );
            for (k, b) in boxes.iter().enumerate() {
                let side = if k < cut { &mut l } else { &mut r };
                side.0 = side.0.min(b.0);
                side.1 = side.1.max(b.1);
                side.2 += b.2;
            }
            if l.2 == 0 || r.2 == 0 {
                continue;
            }
            let cost = area(l.0, l.1) * l.2 as f32 + area(r.0, r.1) * r.2 as f32;
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, cut));
            }
        }
    }
    let (_, axis, cut) = best?;
    let bin_of = |c: f32| (((c - clo[axis]) / extent[axis] * BINS as f32) as usize).min(BINS - 1);
    let mut left = 0;
    for k in 0..items.len() {
        if bin_of(items[k].centre[axis]) < cut {
            items.swap(k, left);
            left += 1;
        }
    }
    (left > 0 && left < items.len()).then_some(left)
}

#[cfg(any(test, feature = "twins"))]
fn slab(node: &GpuBvhNode, o: [f32; 3], inv: [f32; 3], t_max: f32) -> bool {
    let mut t0 = 0.0f32;
    let mut t1 = t_max;
    for a in 0..3 {
        let ta = (node.min[a] - o[a]) * inv[a];
        let tb = (node.max[a] - o[a]) * inv[a];
        // NaN (0 · ∞ on a box face) compares false: min/max pick the other operand, as in WGSL.
        t0 = max_f(t0, min_f(ta, tb));
        t1 = min_f(t1, max_f(ta, tb));
    }
    t0 <= t1
}

#[cfg(any(test, feature = "twins"))]
fn min_f(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}
#[cfg(any(test, feature = "twins"))]
fn max_f(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

#[cfg(any(test, feature = "twins"))]
fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
#[cfg(any(test, feature = "twins"))]
fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Möller–Trumbore, two-sided, edges closed.
#[cfg(any(test, feature = "twins"))]
fn hit(t: &GpuTriangle, o: [f32; 3], d: [f32; 3], t_max: f32) -> bool {
    let v0 = [t.v0[0], t.v0[1], t.v0[2]];
    let e1 = [t.e1[0], t.e1[1], t.e1[2]];
    let e2 = [t.e2[0], t.e2[1], t.e2[2]];
    let p = cross(d, e2);
    let det = dot(e1, p);
    if det.abs() < 1e-20 {
        return false;
    }
    let inv = 1.0 / det;
    let s = [o[0] - v0[0], o[1] - v0[1], o[2] - v0[2]];
    let u = dot(s, p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let q = cross(s, e1);
    let v = dot(d, q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let dist = dot(e2, q) * inv;
    dist > 0.0 && dist < t_max
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bvh_agrees_with_brute_force() {
        let mut tris = Vec::new();
        let mut s = 7u64;
        let mut r = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 40) as f32) / (1u64 << 24) as f32 * 2.0 - 1.0
        };
        for _ in 0..300 {
            let c = Vec3::new(r(), r(), r()) * 5.0;
            tris.push([
                c,
                c + Vec3::new(r(), r(), r()) * 2.0,
                c + Vec3::new(r(), r(), r()) * 2.0,
            ]);
        }
        let bvh = Bvh::build(&tris);
        assert_eq!(bvh.triangles.len(), 300);
        let flat = Bvh {
            nodes: vec![GpuBvhNode {
                min: [-1e9; 3],
                left_first: 0,
                max: [1e9; 3],
                count: 300,
            }],
            triangles: Bvh::build(&tris).triangles,
            source: Vec::new(),
            depth: 1,
        };
        let mut hits = 0;
        for _ in 0..2000 {
            let o = [r() * 6.0, r() * 6.0, r() * 6.0];
            let d = Vec3::new(r(), r(), r()).normalize_or_zero().to_array();
            let a = bvh.occluded(o, d, 100.0);
            assert_eq!(a, flat.occluded(o, d, 100.0), "ray {o:?} {d:?}");
            hits += a as u32;
        }
        assert!(
            hits > 100 && hits < 1900,
            "{hits} of 2000 rays hit: the test scene is degenerate"
        );
    }
}
