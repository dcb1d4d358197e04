//! `V(p)` for the light kinds other than the rectangle (docs/lights.md §2). Each emitter is a flat
//! disk sampled uniformly by area, as the rectangle is: the disk itself; the sun's disk at
//! infinity (a disk of directions of radius `tan(α/2)` one unit out); the sphere's silhouette seen
//! from `p` (the disk of directions that just touches the sphere, rays ending on its near surface).
//! The unit square's samples (the rectangle's, same strata, same seeds) go to the unit disk by the
//! concentric map, which keeps the strata compact.
//!
//! `vis = 0` as for the rectangle (method.md §1): at or below `p`'s tangent plane, or blocked on
//! `(0, dist·(1 - LIGHT_END_EPS))`; and `V = 0` for `p` on or behind the disk's plane, or inside
//! the sphere.

use super::visibility::LIGHT_END_EPS;
use super::{ReferenceError, ReferenceMode, SurfacePoint, Tracer};
use glam::Vec3;
use rayon::prelude::*;
use std::sync::Mutex;

/// A light the reference samples besides the rectangle (`RefLight`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RefEmitter {
    /// A disk of `radius` around `center`, emitting on the side of the unit `normal`.
    Disk {
        center: Vec3,
        normal: Vec3,
        radius: f32,
    },
    /// Directions `normalize(toward + tan_half·q)`, `q` in the unit disk across `toward`; rays
    /// end `reach` away (past every triangle).
    Sun {
        toward: Vec3,
        tan_half: f32,
        reach: f32,
    },
    /// An emitter sphere, sampled as seen from each receiver.
    Sphere { center: Vec3, radius: f32 },
    /// The spot light's emitter sphere (its cone scales lighting, not V): sampled as `Sphere` by
    /// the continuous reference; the lattice and point modes take its maps' own light points
    /// (`spot_light_point` from the stand-in square `light`).
    Spot { light: AreaLight, spot: SpotLight },
    /// The point light's emitter sphere: sampled as `Sphere` by the continuous reference; the
    /// lattice and point modes take the cube maps' own light points (`point_light_point` on the
    /// face that holds the receiver), so they are the exact visibility at a grid's points.
    Point { center: Vec3, radius: f32 },
}

impl RefEmitter {
    /// Bytes that identify it in a cache key.
    pub fn key_bytes(&self) -> Vec<u8> {
        let (tag, xs): (&[u8], Vec<f32>) = match *self {
            RefEmitter::Disk {
                center,
                normal,
                radius,
            } => (
                b"disk",
                [center.to_array(), normal.to_array()]
                    .concat()
                    .into_iter()
                    .chain([radius])
                    .collect(),
            ),
            RefEmitter::Sun {
                toward,
                tan_half,
                reach,
            } => (
                b"sun",
                toward
                    .to_array()
                    .into_iter()
                    .chain([tan_half, reach])
                    .collect(),
            ),
            RefEmitter::Sphere { center, radius } => (
                b"sphere",
                center.to_array().into_iter().chain([radius]).collect(),
            ),
            RefEmitter::Point { center, radius } => (
                b"point-sphere",
                center.to_array().into_iter().chain([radius]).collect(),
            ),
            RefEmitter::Spot { light, spot } => (
                b"spot-ball",
                [
                    spot.position,
                    spot.direction,
                    light.center,
                    light.edge_u,
                    light.edge_v,
                ]
                .iter()
                .flat_map(|v| v.to_array())
                .chain([spot.radius])
                .collect(),
            ),
        };
        let mut v = tag.to_vec();
        xs.iter()
            .for_each(|x| v.extend_from_slice(&x.to_le_bytes()));
        v
    }

    fn check(&self) -> Result<(), ReferenceError> {
        let ok = match *self {
            RefEmitter::Disk {
                center,
                normal,
                radius,
            } => center.is_finite() && normal.is_normalized() && radius > 0.0 && radius.is_finite(),
            RefEmitter::Sun {
                toward,
                tan_half,
                reach,
            } => toward.is_normalized() && tan_half > 0.0 && tan_half.is_finite() && reach > 0.0,
            RefEmitter::Sphere { center, radius } | RefEmitter::Point { center, radius } => {
                center.is_finite() && radius > 0.0 && radius.is_finite()
            }
            RefEmitter::Spot { light, spot } => {
                spot.position.is_finite()
                    && spot.radius > 0.0
                    && spot.radius.is_finite()
                    && spot.direction.is_normalized()
                    && light.edge_u.is_finite()
                    && light.edge_v.is_finite()
            }
        };
        if ok {
            Ok(())
        } else {
            Err(ReferenceError::DegenerateLight)
        }
    }
}

/// The concentric map lives with the emitters, which the methods' samples share.
pub use crate::scene::emitter::concentric;
use crate::scene::emitter::{cube_face, point_light_point, spot_light_point};
use crate::scene::light::AreaLight;
use crate::scene::{PointLight, SpotLight};

/// The maps' own light points, which the lattice and point modes of the point and the spot trace
/// to, so that they are the exact visibility at a grid's points.
enum MapPoints {
    /// `point_light_point` on the face that holds the receiver.
    Cube(PointLight),
    Spot(AreaLight, SpotLight),
}

impl MapPoints {
    fn of(emitter: &RefEmitter, mode: &ReferenceMode) -> Option<MapPoints> {
        match (*emitter, mode) {
            (
                RefEmitter::Point { center, radius },
                ReferenceMode::Lattice | ReferenceMode::Point { .. },
            ) => Some(MapPoints::Cube(PointLight {
                position: center,
                radius,
            })),
            (
                RefEmitter::Spot { light, spot },
                ReferenceMode::Lattice | ReferenceMode::Point { .. },
            ) => Some(MapPoints::Spot(light, spot)),
            _ => None,
        }
    }

    /// The emitter sphere's centre and radius.
    fn sphere(&self) -> (Vec3, f32) {
        match self {
            MapPoints::Cube(l) => (l.position, l.radius),
            MapPoints::Spot(_, spot) => (spot.position, spot.radius),
        }
    }

    /// Sample `(s, t)`'s light point for a receiver at `to_p` from the centre.
    fn point(&self, to_p: Vec3, s: f32, t: f32) -> Vec3 {
        match self {
            MapPoints::Cube(l) => point_light_point(l, cube_face(to_p), s, t),
            MapPoints::Spot(light, spot) => spot_light_point(light, spot, s, t),
        }
    }
}

/// The unit-square points of `mode` for `pixel`: the rectangle's (s, t), in its order and seeds.
pub fn fill_unit_samples(mode: &ReferenceMode, pixel: u64, out: &mut Vec<(f32, f32)>) {
    out.clear();
    super::sampling::for_each_unit_sample(mode, pixel, |s, t| out.push((s, t)));
}

/// Two unit vectors across the unit `n` (Duff et al. 2017: continuous except at one sign flip).
pub fn basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// `V` for every point under `emitter` (`None` points give 0), in parallel; as
/// `try_trace_visibility` does for the rectangle.
pub fn try_trace_emitter(
    tracer: &Tracer,
    points: &[Option<SurfacePoint>],
    emitter: &RefEmitter,
    mode: &ReferenceMode,
    ray_offset: f32,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Vec<f32>, ReferenceError> {
    emitter.check()?;
    if mode.samples_per_pixel() == 0 {
        return Err(ReferenceError::NoSamples);
    }
    let map_points = MapPoints::of(emitter, mode);
    const CHUNK: usize = 256;
    let mut out = vec![0.0f32; points.len()];
    let done = Mutex::new(0usize);
    out.par_chunks_mut(CHUNK)
        .zip(points.par_chunks(CHUNK))
        .enumerate()
        .for_each(|(chunk, (out, points))| {
            let mut unit = Vec::with_capacity(mode.samples_per_pixel());
            let mut rays = 0u64;
            for (k, (v, point)) in out.iter_mut().zip(points).enumerate() {
                let Some(point) = point else { continue };
                fill_unit_samples(mode, (chunk * CHUNK + k) as u64, &mut unit);
                let (value, n) = match &map_points {
                    Some(points) => map_point_visibility(tracer, point, points, &unit, ray_offset),
                    None => emitter_visibility(tracer, point, emitter, &unit, ray_offset),
                };
                *v = value;
                rays += n;
            }
            tracer.add_rays(rays);
            let mut done = done.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
            *done += out.len();
            progress(*done);
        });
    Ok(out)
}

/// `(V, rays traced)` at one point for unit-square samples `unit`.
pub fn emitter_visibility(
    tracer: &Tracer,
    point: &SurfacePoint,
    emitter: &RefEmitter,
    unit: &[(f32, f32)],
    ray_offset: f32,
) -> (f32, u64) {
    let p = point.position;
    let normal = point.normal.normalize_or_zero();
    if unit.is_empty() || !p.is_finite() || normal == Vec3::ZERO || !ray_offset.is_finite() {
        return (0.0, 0);
    }
    let origin = p + normal * ray_offset;
    // Per kind: where a unit-disk point `q` sends the ray, as (unit direction, length).
    let (axis, spread, end): (Vec3, f32, End) = match *emitter {
        RefEmitter::Disk {
            center,
            normal: n,
            radius,
        } => {
            if (p - center).dot(n) <= 0.0 {
                return (0.0, 0); // on or behind the disk's plane: unlit
            }
            (n, radius, End::Disk { center })
        }
        RefEmitter::Sun {
            toward,
            tan_half,
            reach,
        } => (toward, tan_half, End::Far { reach }),
        RefEmitter::Sphere { center, radius }
        | RefEmitter::Point { center, radius }
        | RefEmitter::Spot {
            spot:
                SpotLight {
                    position: center,
                    radius,
                    ..
                },
            ..
        } => {
            let to_c = center - p;
            let d2 = to_c.length_squared();
            if d2 <= radius * radius {
                return (0.0, 0); // inside the emitter
            }
            let d = d2.sqrt();
            (
                to_c / d,
                radius / (d2 - radius * radius).sqrt(),
                End::Sphere { center, radius },
            )
        }
    };
    let (u, v) = basis(axis);
    let (mut lit, mut rays) = (0u32, 0u64);
    for &(s, t) in unit {
        let (qx, qy) = concentric(s, t);
        let across = (u * qx + v * qy) * spread;
        // The sample's unit direction from the ray origin and the distance to the emitter.
        let (dir, dist) = match end {
            End::Disk { center } => {
                let y = center + across;
                if normal.dot(y - p) <= 0.0 {
                    continue; // at or below the tangent plane
                }
                let seg = y - origin;
                (seg.normalize_or_zero(), seg.length())
            }
            End::Far { reach } => {
                let w = (axis + across).normalize();
                if normal.dot(w) <= 0.0 {
                    continue;
                }
                (w, reach)
            }
            End::Sphere { center, radius } => {
                let w = (axis + across).normalize();
                // The near surface along w from p: |p + t·w - c| = r.
                let b = w.dot(center - p);
                let disc = (b * b - ((center - p).length_squared() - radius * radius)).max(0.0);
                let y = p + w * (b - disc.sqrt());
                if normal.dot(y - p) <= 0.0 {
                    continue;
                }
                let seg = y - origin;
                (seg.normalize_or_zero(), seg.length())
            }
        };
        let blocked = dist > 0.0 && {
            rays += 1;
            tracer.occluded_uncounted(origin, dir, dist * (1.0 - LIGHT_END_EPS))
        };
        lit += (!blocked) as u32;
    }
    (lit as f32 / unit.len() as f32, rays)
}

/// `(V, rays traced)` at one point for the maps' own light points of unit-square samples `unit`:
/// the rules of `emitter_visibility` (unlit inside the sphere or at or below the tangent plane).
fn map_point_visibility(
    tracer: &Tracer,
    point: &SurfacePoint,
    points: &MapPoints,
    unit: &[(f32, f32)],
    ray_offset: f32,
) -> (f32, u64) {
    let p = point.position;
    let normal = point.normal.normalize_or_zero();
    let (center, radius) = points.sphere();
    let to_p = p - center;
    if unit.is_empty()
        || !p.is_finite()
        || normal == Vec3::ZERO
        || !ray_offset.is_finite()
        || to_p.length_squared() <= radius * radius
    {
        return (0.0, 0);
    }
    let origin = p + normal * ray_offset;
    let (mut lit, mut rays) = (0u32, 0u64);
    for &(s, t) in unit {
        let y = points.point(to_p, s, t);
        if normal.dot(y - p) <= 0.0 {
            continue;
        }
        let seg = y - origin;
        let dist = seg.length();
        let blocked = dist > 0.0 && {
            rays += 1;
            tracer.occluded_uncounted(origin, seg / dist, dist * (1.0 - LIGHT_END_EPS))
        };
        lit += (!blocked) as u32;
    }
    (lit as f32 / unit.len() as f32, rays)
}

#[derive(Clone, Copy)]
enum End {
    Disk { center: Vec3 },
    Far { reach: f32 },
    Sphere { center: Vec3, radius: f32 },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_concentric_map_keeps_area_and_stays_in_the_disk() {
        // Uniform square → uniform disk: the share of a 32×32 grid inside radius ρ is ρ².
        let n = 64;
        let mut inside_half = 0;
        for j in 0..n {
            for i in 0..n {
                let (x, y) = concentric((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let r2 = x * x + y * y;
                assert!(r2 <= 1.0 + 1e-6);
                inside_half += (r2 < 0.25) as u32;
            }
        }
        let share = inside_half as f32 / (n * n) as f32;
        assert!((share - 0.25).abs() < 0.01, "{share}");
        assert_eq!(concentric(0.5, 0.5), (0.0, 0.0));
    }

    #[test]
    fn the_basis_is_orthonormal() {
        for n in [
            Vec3::Y,
            Vec3::NEG_Z,
            Vec3::new(0.3, -0.8, 0.52).normalize(),
            Vec3::new(-0.7, 0.1, -0.7).normalize(),
        ] {
            let (u, v) = basis(n);
            assert!(u.dot(v).abs() < 1e-5 && u.dot(n).abs() < 1e-5 && v.dot(n).abs() < 1e-5);
            assert!((u.length() - 1.0).abs() < 1e-5 && (v.length() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn unit_samples_are_the_rectangles_strata() {
        use crate::reference::RefLight;
        let light = RefLight {
            center: Vec3::ZERO,
            edge_u: Vec3::X,
            edge_v: Vec3::Z,
        };
        let mode = ReferenceMode::Continuous { m: 8, seed: 7 };
        let (mut rect, mut unit) = (Vec::new(), Vec::new());
        crate::reference::sampling::fill_light_samples(&mode, &light, 5, &mut rect);
        fill_unit_samples(&mode, 5, &mut unit);
        for (y, (s, t)) in rect.iter().zip(&unit) {
            assert_eq!(*y, light.point(*s, *t));
        }
    }

    #[test]
    fn a_sphere_behind_a_coaxial_disk_matches_the_closed_form_on_the_axis() {
        use crate::reference::analytic_lights::sphere_behind_disk_on_axis;
        // A 512-gon of radius a at height h: its area is within 3e-5 of the disk's.
        let (a, h, n) = (0.4f32, 2.0f32, 512);
        let rim = |k: usize| {
            let t = k as f32 / n as f32 * std::f32::consts::TAU;
            Vec3::new(a * t.cos(), h, a * t.sin())
        };
        let tris: Vec<[Vec3; 3]> = (0..n)
            .map(|k| [Vec3::new(0.0, h, 0.0), rim(k), rim(k + 1)])
            .collect();
        let tracer = Tracer::new(&tris);
        let point = SurfacePoint {
            position: Vec3::ZERO,
            normal: Vec3::Y,
        };
        let mut unit = Vec::new();
        for (d, r) in [(6.0f32, 1.5f32), (5.0, 2.5), (8.0, 1.8)] {
            let sphere = RefEmitter::Sphere {
                center: Vec3::new(0.0, d, 0.0),
                radius: r,
            };
            fill_unit_samples(&ReferenceMode::Continuous { m: 64, seed: 3 }, 0, &mut unit);
            let (v, _) = emitter_visibility(&tracer, &point, &sphere, &unit, 0.0);
            let exact = sphere_behind_disk_on_axis(d as f64, r as f64, h as f64, a as f64);
            assert!(
                (v as f64 - exact).abs() < 2e-3,
                "d {d}, r {r}: traced {v}, exact {exact}"
            );
            assert!(
                exact > 0.05 && exact < 0.95,
                "d {d}, r {r}: {exact} is not a penumbra"
            );
        }
    }

    /// The half-plane x > 0 at height `h`, two triangles 50 units across.
    fn half_plane(h: f32) -> Tracer {
        let g = 50.0f32;
        Tracer::new(&[
            [
                Vec3::new(0.0, h, -g),
                Vec3::new(g, h, -g),
                Vec3::new(g, h, g),
            ],
            [
                Vec3::new(0.0, h, -g),
                Vec3::new(g, h, g),
                Vec3::new(0.0, h, g),
            ],
        ])
    }

    #[test]
    fn lattice_and_point_modes_count_the_mapped_points_exactly() {
        // The sun overhead, a half-plane x > 0 at height 1.
        let h = 1.0f32;
        let tracer = half_plane(h);
        let sun = RefEmitter::Sun {
            toward: Vec3::Y,
            tan_half: 0.2,
            reach: 100.0,
        };
        let mut unit = Vec::new();
        for x in [-0.173f32, -0.061, 0.052, 0.149] {
            let point = SurfacePoint {
                position: Vec3::new(x, 0.0, 0.3),
                normal: Vec3::Y,
            };
            fill_unit_samples(&ReferenceMode::Lattice, 0, &mut unit);
            assert_eq!(unit.len(), 289);
            let (v, _) = emitter_visibility(&tracer, &point, &sun, &unit, 0.0);
            // Blocked iff the direction's crossing of y = h lies at x > 0 (its x offset is h·tan·q.x).
            let lit = unit
                .iter()
                .filter(|&&(s, t)| x + h * 0.2 * concentric(s, t).0 <= 0.0)
                .count();
            assert_eq!(v, lit as f32 / 289.0, "x = {x}");
            assert!(lit > 0 && lit < 289, "x = {x}: not in the penumbra");
            // The centre of the sun: the hard shadow of the edge.
            fill_unit_samples(&ReferenceMode::Point { s: 0.5, t: 0.5 }, 0, &mut unit);
            let (v, _) = emitter_visibility(&tracer, &point, &sun, &unit, 0.0);
            assert_eq!(v, if x < 0.0 { 1.0 } else { 0.0 }, "x = {x}");
        }
    }

    #[test]
    fn the_point_lights_lattice_and_point_modes_trace_to_its_cube_points() {
        // The sphere at height 6 over a half-plane x > 0 at height 3; ground receivers hold face −y.
        // Each lattice point y is blocked iff the segment from p crosses y = 3 at x > 0: counted
        // exactly from `point_light_point`, while the continuous mode still samples the silhouette.
        let h = 3.0f32;
        let tracer = half_plane(h);
        let light = PointLight {
            position: Vec3::new(1.0, 6.0, 0.5),
            radius: 1.5,
        };
        let emitter = RefEmitter::Point {
            center: light.position,
            radius: light.radius,
        };
        let points: Vec<Option<SurfacePoint>> = [-2.2f32, -1.4, -0.9, -0.3]
            .iter()
            .map(|&x| {
                Some(SurfacePoint {
                    position: Vec3::new(x, 0.0, 3.5),
                    normal: Vec3::Y,
                })
            })
            .collect();
        let v = try_trace_emitter(
            &tracer,
            &points,
            &emitter,
            &ReferenceMode::Lattice,
            0.0,
            &|_| {},
        )
        .unwrap();
        let mut unit = Vec::new();
        fill_unit_samples(&ReferenceMode::Lattice, 0, &mut unit);
        for (p, v) in points.iter().flatten().zip(&v) {
            let lit = unit.iter().filter(|&&(s, t)| {
                let y = point_light_point(&light, 3, s, t);
                let x_at = p.position.x + (y.x - p.position.x) * h / y.y;
                x_at <= 0.0
            });
            let lit = lit.count();
            assert_eq!(*v, lit as f32 / 289.0, "x = {}", p.position.x);
            assert!(
                lit > 0 && lit < 289,
                "x = {}: not in the penumbra",
                p.position.x
            );
        }
        let centre = try_trace_emitter(
            &tracer,
            &points,
            &emitter,
            &ReferenceMode::Point { s: 0.5, t: 0.5 },
            0.0,
            &|_| {},
        )
        .unwrap();
        // The centre alone: the hard shadow's edge at x = 1 − 1·6/3 = −1.
        assert_eq!(centre, [1.0, 1.0, 0.0, 0.0]);
    }

    #[test]
    fn the_spots_lattice_mode_traces_to_its_maps_points() {
        // The point light's case with a spot tilted 20° off the vertical: each lattice point from
        // `spot_light_point` is counted exactly; the continuous mode differs from that count.
        use crate::scene::Emitter;
        let h = 3.0f32;
        let tracer = half_plane(h);
        let spot = SpotLight {
            position: Vec3::new(1.0, 6.0, 0.5),
            direction: Vec3::new(0.342, -0.94, 0.0).normalize(),
            inner_cone_deg: 30.0,
            outer_cone_deg: 50.0,
            radius: 1.5,
        };
        let light = Emitter::Spot(spot)
            .stand_in(&crate::scene::light::Bounds {
                min: Vec3::splat(-5.0),
                max: Vec3::splat(5.0),
            })
            .unwrap();
        let emitter = RefEmitter::Spot { light, spot };
        let points: Vec<Option<SurfacePoint>> = [-2.2f32, -1.4, -0.9, -0.3]
            .iter()
            .map(|&x| {
                Some(SurfacePoint {
                    position: Vec3::new(x, 0.0, 3.5),
                    normal: Vec3::Y,
                })
            })
            .collect();
        let v = try_trace_emitter(
            &tracer,
            &points,
            &emitter,
            &ReferenceMode::Lattice,
            0.0,
            &|_| {},
        )
        .unwrap();
        let continuous = try_trace_emitter(
            &tracer,
            &points,
            &emitter,
            &ReferenceMode::Continuous { m: 17, seed: 1 },
            0.0,
            &|_| {},
        )
        .unwrap();
        let mut unit = Vec::new();
        fill_unit_samples(&ReferenceMode::Lattice, 0, &mut unit);
        for ((p, v), c) in points.iter().flatten().zip(&v).zip(&continuous) {
            let lit = unit.iter().filter(|&&(s, t)| {
                let y = spot_light_point(&light, &spot, s, t);
                p.position.x + (y.x - p.position.x) * h / y.y <= 0.0
            });
            let lit = lit.count();
            assert_eq!(*v, lit as f32 / 289.0, "x = {}", p.position.x);
            assert!(
                lit > 0 && lit < 289,
                "x = {}: not in the penumbra",
                p.position.x
            );
            assert_ne!(
                v, c,
                "x = {}: the continuous mode traced the same points",
                p.position.x
            );
        }
    }
}
