//! BVH wrapper: obvhs CWBVH for traversal, our own watertight triangle test for the hits.
//!
//! obvhs' `Triangle::intersect` (Möller–Trumbore with a sign-bit test) says of itself that it is
//! not watertight, and its edges are closed for `+0.0` barycentrics but open for `-0.0`. The
//! lattice reference must agree exactly with a geometric count under a stated boundary rule, so
//! primitives are tested with Woop, Benthin & Wald 2013 ("Watertight ray/triangle intersection"):
//! two-sided, edges and vertices closed (a ray through an edge hits), exact by construction, and
//! as fast as obvhs' test here (axis permutation resolved at compile time).

use glam::{Vec3, Vec3A};
use obvhs::{aabb::Aabb, cwbvh::builder::build_cwbvh, cwbvh::CwBvh, ray::Ray, BvhBuildParams};
use obvhs::{ray::RayHit, triangle::Triangle};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

/// Closest hit: `t` in units of the query's `|dir|`, and the input triangle index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub triangle: u32,
    /// Unit geometric normal `(v1-v0)×(v2-v0)` of the hit triangle (not flipped to face the ray).
    pub normal: Vec3,
}

/// A CPU ray tracer over a fixed triangle soup. `Sync`: share one across rayon workers.
pub struct Tracer {
    bvh: CwBvh,
    /// Triangles in BVH leaf order (`bvh.primitive_indices` applied), so leaves index them directly.
    tris: Vec<Triangle>,
    /// Input index of each entry of `tris`.
    source: Vec<u32>,
    skipped: usize,
    rays: AtomicU64,
}

impl Tracer {
    /// Builds the BVH. Triangles with a non-finite vertex are skipped (see [`Tracer::skipped_triangles`]);
    /// an empty scene is valid and occludes nothing.
    pub fn new(triangles: &[[Vec3; 3]]) -> Tracer {
        let mut kept = Vec::with_capacity(triangles.len());
        let mut kept_index = Vec::with_capacity(triangles.len());
        for (i, t) in triangles.iter().enumerate() {
            if t.iter().all(|v| v.is_finite()) {
                kept.push(Triangle {
                    v0: t[0].into(),
                    v1: t[1].into(),
                    v2: t[2].into(),
                });
                kept_index.push(i as u32);
            }
        }
        let skipped = triangles.len() - kept.len();
        if kept.is_empty() {
            return Tracer {
                bvh: CwBvh::default(),
                tris: Vec::new(),
                source: Vec::new(),
                skipped,
                rays: AtomicU64::new(0),
            };
        }
        // The boxes are padded: obvhs's ray/box test rounds without a margin, so a ray through a
        // triangle's edge on its box's face could be culled (seen on `spot-edge` at 48²: one
        // sample of 2.3 M missed an occluder's open edge that the watertight test hits). Padded by
        // far more than that rounding, the boxes cull no ray the triangle test would hit.
        // (`slow_build`'s pre-split of big triangles works on the triangles themselves, so it is
        // not used: it traced about 1.3× faster.)
        let (lo, hi) = kept.iter().fold(
            (Vec3A::splat(f32::INFINITY), Vec3A::splat(f32::NEG_INFINITY)),
            |(lo, hi), t| {
                (
                    lo.min(t.v0).min(t.v1).min(t.v2),
                    hi.max(t.v0).max(t.v1).max(t.v2),
                )
            },
        );
        let pad =
            Vec3A::splat(BOX_PAD * (hi - lo).length().max(hi.abs().max(lo.abs()).max_element()));
        let boxes: Vec<Aabb> = kept
            .iter()
            .map(|t| {
                let b = t.aabb();
                Aabb {
                    min: b.min - pad,
                    max: b.max + pad,
                }
            })
            .collect();
        let params = BvhBuildParams::slow_build();
        let bvh = build_cwbvh(&boxes, params, &mut Duration::default());
        // With splits an input triangle may appear in several leaves: duplicate it, it's cheap.
        let tris: Vec<Triangle> = bvh
            .primitive_indices
            .iter()
            .map(|&i| kept[i as usize])
            .collect();
        let source = bvh
            .primitive_indices
            .iter()
            .map(|&i| kept_index[i as usize])
            .collect();
        Tracer {
            bvh,
            tris,
            source,
            skipped,
            rays: AtomicU64::new(0),
        }
    }

    /// Number of input triangles dropped for non-finite vertices.
    pub fn skipped_triangles(&self) -> usize {
        self.skipped
    }

    /// Rays traced so far (occlusion and closest-hit queries, all threads).
    pub fn rays_traced(&self) -> u64 {
        self.rays.load(Ordering::Relaxed)
    }

    /// Is there a triangle at `t ∈ (0, t_max)` along `origin + t·dir`? `dir` need not be unit
    /// (`t` is in units of `|dir|`); a zero or non-finite ray reports unoccluded.
    pub fn occluded(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        self.rays.fetch_add(1, Ordering::Relaxed);
        self.occluded_uncounted(origin, dir, t_max)
    }

    /// Closest triangle at `t ∈ (0, t_max)` (use `f32::INFINITY` for an unbounded ray), in units of
    /// `|dir|`. Meant for building a CPU G-buffer in tests and tools.
    pub fn closest_hit(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<Hit> {
        self.rays.fetch_add(1, Ordering::Relaxed);
        let ray = WatertightRay::new(origin, dir)?;
        let (id, t) = match ray.kz {
            0 => self.closest::<1, 2, 0>(&ray, t_max),
            1 => self.closest::<2, 0, 1>(&ray, t_max),
            _ => self.closest::<0, 1, 2>(&ray, t_max),
        }?;
        let tri = &self.tris[id];
        let normal = Vec3::from((tri.v1 - tri.v0).cross(tri.v2 - tri.v0).normalize_or_zero());
        Some(Hit {
            t,
            triangle: self.source[id],
            normal,
        })
    }

    /// `occluded` without touching the shared counter; callers batch counts with [`Tracer::add_rays`]
    /// so worker threads do not fight over one cache line per ray.
    pub(crate) fn occluded_uncounted(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        let Some(ray) = WatertightRay::new(origin, dir) else {
            return false;
        };
        if t_max.is_nan() || t_max <= 0.0 {
            return false;
        }
        // The dominant axis is fixed per ray: dispatch once so the triangle test indexes lanes
        // known at compile time (~20% faster than runtime indexing).
        match ray.kz {
            0 => self.any_hit::<1, 2, 0>(&ray, t_max),
            1 => self.any_hit::<2, 0, 1>(&ray, t_max),
            _ => self.any_hit::<0, 1, 2>(&ray, t_max),
        }
    }

    fn any_hit<const KX: usize, const KY: usize, const KZ: usize>(
        &self,
        ray: &WatertightRay,
        t_max: f32,
    ) -> bool {
        // obvhs's box test clamps a box's entry to t ≥ 1e-4 (its `EPSILON`, in world units), so a
        // box the ray leaves within 1e-4 of its origin is culled, and a hit in it at t > 0 lost
        // (seen on `spot-edge` at 48²: one sample of 2.3 M, found by lab/tests/truth_trace.rs).
        // The traversal starts BOX_LEAD behind the origin, past that clamp; the triangle test keeps
        // the origin and (0, t_max), so the answer is the convention's, whatever the boxes.
        let r = ray.obvhs_led(t_max);
        !self.bvh.ray_traverse_miss(r, |_, id| {
            ray.intersect::<KX, KY, KZ>(&self.tris[id], t_max)
        })
    }

    fn closest<const KX: usize, const KY: usize, const KZ: usize>(
        &self,
        ray: &WatertightRay,
        t_max: f32,
    ) -> Option<(usize, f32)> {
        let mut hit = RayHit::none();
        let r = ray.obvhs(t_max);
        let found = self.bvh.ray_traverse(r, &mut hit, |r, id| {
            ray.intersect::<KX, KY, KZ>(&self.tris[id], r.tmax)
        });
        found.then_some((hit.primitive_id as usize, hit.t))
    }

    pub(crate) fn add_rays(&self, n: u64) {
        self.rays.fetch_add(n, Ordering::Relaxed);
    }
}

/// The padding of every triangle's box, relative to the scene's size: rounding in obvhs's box
/// test is a few ulps of the ray's distances, 1e-6 of them at most.
const BOX_PAD: f32 = 1e-5;

/// How far behind its origin an occlusion ray's traversal starts: twice obvhs's box-entry clamp
/// (1e-4, in units of |dir|), so no box that holds a point at t > 0 is culled by it.
const BOX_LEAD: f32 = 2e-4;

/// Per-ray constants of the watertight test: the ray is sheared so it runs along the +kz axis,
/// which makes the edge functions of a shared edge bitwise negations of each other.
/// (Woop et al. also swap kx/ky when `dir[kz] < 0` to keep the winding; a two-sided, closed test
/// accepts either sign, so the swap is dropped and three axis permutations suffice.)
struct WatertightRay {
    org: Vec3A,
    dir: Vec3A,
    kz: usize,
    /// `(dir[kx]/dir[kz], dir[ky]/dir[kz], 1/dir[kz])` with `kx = kz+1`, `ky = kz+2` (mod 3).
    shear: Vec3A,
}

impl WatertightRay {
    fn new(origin: Vec3, dir: Vec3) -> Option<WatertightRay> {
        if !origin.is_finite() || !dir.is_finite() || dir == Vec3::ZERO {
            return None;
        }
        let a = dir.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let (kx, ky) = ((kz + 1) % 3, (kz + 2) % 3);
        let shear = Vec3A::new(dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]);
        // obvhs picks a node's near/far planes from `direction < 0.0` but inverts with the sign
        // of zero, so a `-0.0` component (e.g. `-Vec3::Y`) makes its slab test inconsistent and
        // the ray misses everything. `x + 0.0` maps `-0.0` to `+0.0` and keeps every other value.
        let dir = Vec3A::from(dir) + Vec3A::ZERO;
        Some(WatertightRay {
            org: origin.into(),
            dir,
            kz,
            shear,
        })
    }

    fn obvhs(&self, t_max: f32) -> Ray {
        Ray::new(self.org, self.dir, 0.0, t_max)
    }

    /// The traversal's ray for occlusion: from BOX_LEAD behind the origin, as far past `t_max`
    /// (t in units of |dir|, as obvhs's clamp is).
    fn obvhs_led(&self, t_max: f32) -> Ray {
        Ray::new(
            self.org - self.dir * BOX_LEAD,
            self.dir,
            0.0,
            t_max + BOX_LEAD,
        )
    }

    /// Hit distance in `(0, t_max)`, else `f32::INFINITY`. `(KX, KY, KZ)` must match `self.kz`.
    #[inline(always)]
    fn intersect<const KX: usize, const KY: usize, const KZ: usize>(
        &self,
        tri: &Triangle,
        t_max: f32,
    ) -> f32 {
        let s = self.shear;
        let a: [f32; 3] = (tri.v0 - self.org).into();
        let b: [f32; 3] = (tri.v1 - self.org).into();
        let c: [f32; 3] = (tri.v2 - self.org).into();
        let (ax, ay) = (a[KX] - s.x * a[KZ], a[KY] - s.y * a[KZ]);
        let (bx, by) = (b[KX] - s.x * b[KZ], b[KY] - s.y * b[KZ]);
        let (cx, cy) = (c[KX] - s.x * c[KZ], c[KY] - s.y * c[KZ]);
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            // Products of f32 are exact in f64, so the sign of an edge function is exact here.
            let d = |px: f32, py: f32, qx: f32, qy: f32| {
                (px as f64 * qy as f64 - py as f64 * qx as f64) as f32
            };
            u = d(cx, cy, bx, by);
            v = d(ax, ay, cx, cy);
            w = d(bx, by, ax, ay);
        }
        // Two-sided, closed: reject only when the ray is strictly outside some edge.
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return f32::INFINITY;
        }
        let det = u + v + w;
        if det == 0.0 {
            return f32::INFINITY; // ray in the triangle's plane, or a degenerate triangle
        }
        let t = (u * (s.z * a[KZ]) + v * (s.z * b[KZ]) + w * (s.z * c[KZ])) / det;
        if t > 0.0 && t < t_max {
            t
        } else {
            f32::INFINITY
        }
    }
}
