//! The light's kind and shape (docs/lights.md): the rectangle, the disk, the sun and the spot,
//! which the map-based methods sample through `Emitter::sample_map`, and the point, whose samples
//! are cube maps (`Emitter::sample_maps`).

use super::light::{cube_face_view, orthographic_view, sample_view, AreaLight, Bounds};
use crate::gpu::structs::GpuSample;
use glam::Vec3;

/// The `kind` key of `[light]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LightKind {
    #[default]
    Rect,
    Disk,
    Sun,
    Spot,
    Point,
}

impl LightKind {
    pub fn name(self) -> &'static str {
        match self {
            LightKind::Rect => "rect",
            LightKind::Disk => "disk",
            LightKind::Sun => "sun",
            LightKind::Spot => "spot",
            LightKind::Point => "point",
        }
    }
}

/// A disk of `radius` around `center`, emitting on the side of the unit `normal`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiskLight {
    pub center: Vec3,
    pub normal: Vec3,
    pub radius: f32,
}

/// The area light at infinity: a disk of directions of `angular_diameter_deg` around the unit
/// `direction` the light travels in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunLight {
    pub direction: Vec3,
    pub angular_diameter_deg: f32,
}

impl SunLight {
    /// Unit vector towards the sun's centre.
    pub fn toward(&self) -> Vec3 {
        -self.direction
    }
    /// Tangent of the angular radius: the radius of the disk of directions one unit away.
    pub fn tan_half_angle(&self) -> f32 {
        (0.5 * self.angular_diameter_deg).to_radians().tan()
    }
}

/// An emitter sphere of `radius` at `position`, lighting the cone around the unit `direction`:
/// fully inside `inner_cone_deg`, not at all beyond `outer_cone_deg` (half-angles from the axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotLight {
    pub position: Vec3,
    pub direction: Vec3,
    pub inner_cone_deg: f32,
    pub outer_cone_deg: f32,
    pub radius: f32,
}

impl SpotLight {
    /// The cone's illumination factor at `p`: 1 inside the inner cone, 0 beyond the outer one,
    /// smoothstep in the cosine between. It scales the lighting, not V (docs/lights.md).
    pub fn cone_factor(&self, p: Vec3) -> f32 {
        let to_p = (p - self.position).normalize_or_zero();
        let cos = to_p.dot(self.direction);
        let (cos_in, cos_out) = (
            self.inner_cone_deg.to_radians().cos(),
            self.outer_cone_deg.to_radians().cos(),
        );
        if cos >= cos_in {
            return 1.0;
        }
        if cos <= cos_out {
            return 0.0;
        }
        let x = (cos - cos_out) / (cos_in - cos_out);
        x * x * (3.0 - 2.0 * x)
    }
}

/// An emitter sphere of `radius` at `position`, lighting every direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    pub radius: f32,
}

/// The scene's light. `Rect` carries nothing: its rectangle is `Scene::light`, which every
/// rectangle method reads (and studies move). For the other kinds `Scene::light` is a stand-in
/// square ([`Emitter::stand_in`]): the frame's shading direction and lit side, and the axes and
/// size `sample_map` takes for the disk, the sun and the spot; the methods refuse the pairs they
/// cannot run (`ShadowMethod::unsupported_light`).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Emitter {
    #[default]
    Rect,
    Disk(DiskLight),
    Sun(SunLight),
    Spot(SpotLight),
    Point(PointLight),
}

impl Emitter {
    pub fn kind(&self) -> LightKind {
        match self {
            Emitter::Rect => LightKind::Rect,
            Emitter::Disk(_) => LightKind::Disk,
            Emitter::Sun(_) => LightKind::Sun,
            Emitter::Spot(_) => LightKind::Spot,
            Emitter::Point(_) => LightKind::Point,
        }
    }

    /// The same emitter `k` times the size: the disk's, the spot's and the point's radius, the
    /// sun's angular diameter (the framing study's light scale). The rectangle is `Scene::light`.
    pub fn scaled(&self, k: f32) -> Emitter {
        match *self {
            Emitter::Rect => Emitter::Rect,
            Emitter::Disk(d) => Emitter::Disk(DiskLight {
                radius: d.radius * k,
                ..d
            }),
            Emitter::Sun(s) => Emitter::Sun(SunLight {
                angular_diameter_deg: s.angular_diameter_deg * k,
                ..s
            }),
            Emitter::Spot(s) => Emitter::Spot(SpotLight {
                radius: s.radius * k,
                ..s
            }),
            Emitter::Point(p) => Emitter::Point(PointLight {
                radius: p.radius * k,
                ..p
            }),
        }
    }

    /// The same emitter moved by `by` (a sequence's moving light; `Scene::light` moves with it).
    /// A sun is at infinity and a rectangle is `Scene::light` itself: both are returned as they are.
    pub(crate) fn moved(&self, by: Vec3) -> Emitter {
        match *self {
            Emitter::Disk(d) => Emitter::Disk(DiskLight {
                center: d.center + by,
                ..d
            }),
            Emitter::Spot(s) => Emitter::Spot(SpotLight {
                position: s.position + by,
                ..s
            }),
            Emitter::Point(p) => Emitter::Point(PointLight {
                position: p.position + by,
                ..p
            }),
            Emitter::Rect | Emitter::Sun(_) => *self,
        }
    }

    /// A square with the emitter's place and size, facing the meshes: the shading direction of
    /// the frame (and the nominal light of the checks that read `Scene::light`). `None` for `Rect`.
    pub fn stand_in(&self, bounds: &Bounds) -> Option<AreaLight> {
        let mid = bounds.min.lerp(bounds.max, 0.5);
        let (center, normal, side) = match *self {
            Emitter::Rect => return None,
            Emitter::Disk(d) => (d.center, d.normal, 2.0 * d.radius),
            Emitter::Sun(s) => {
                // One scene diagonal out along the sun: every corner lies in front of it.
                let far = bounds.diagonal().max(1e-3);
                (
                    mid - s.direction * far,
                    s.direction,
                    2.0 * far * s.tan_half_angle(),
                )
            }
            Emitter::Spot(s) => (s.position, s.direction, 2.0 * s.radius),
            Emitter::Point(p) => {
                let to_mid = (mid - p.position).normalize_or_zero();
                (
                    p.position,
                    if to_mid == Vec3::ZERO {
                        Vec3::NEG_Y
                    } else {
                        to_mid
                    },
                    2.0 * p.radius,
                )
            }
        };
        let (edge_u, edge_v) = square_edges(normal, side);
        Some(AreaLight {
            center,
            edge_u,
            edge_v,
        })
    }
    /// The light point of unit-square sample `(s, t)` for a method that rasterizes maps from
    /// points on the emitter: the rectangle's `light.point(s, t)`; on the disk the point the
    /// concentric map sends `(s, t)` to, as the reference samples it (`light` is the disk's
    /// stand-in square, whose half-edges are the disk's radius). The spot's sphere is sampled in
    /// its ball (`spot_light_point`), whose projection towards every receiver is, over the samples,
    /// the silhouette the reference samples (docs/lights.md, "Maps on the spot").
    pub fn sample_point(&self, light: &AreaLight, s: f32, t: f32) -> Vec3 {
        match self {
            Emitter::Disk(_) => {
                let (x, y) = concentric(s, t);
                light.point(0.5 + 0.5 * x, 0.5 + 0.5 * y)
            }
            Emitter::Spot(spot) => spot_light_point(light, spot, s, t),
            _ => light.point(s, t),
        }
    }
}

impl Emitter {
    /// The map of unit-square sample `(s, t)` for the methods that rasterize maps from the emitter:
    /// a perspective map from `sample_point` (rectangle, disk, spot); for the sun an orthographic map
    /// along the direction the concentric map sends `(s, t)` to on the sun's disk of directions
    /// (radius `tan(α/2)` around `toward`, as the reference samples it). Each is fitted to `bounds`.
    pub(crate) fn sample_map(
        &self,
        light: &AreaLight,
        s: f32,
        t: f32,
        bounds: &Bounds,
        map_size: u32,
        lattice: u32,
    ) -> GpuSample {
        match self {
            Emitter::Sun(sun) => {
                let (x, y) = concentric(s, t);
                let (u, v) = (light.edge_u.normalize(), light.edge_v.normalize());
                let toward = (sun.toward() + sun.tan_half_angle() * (u * x + v * y)).normalize();
                orthographic_view(toward, u, bounds, map_size, lattice)
            }
            _ => sample_view(
                light,
                self.sample_point(light, s, t),
                bounds,
                map_size,
                lattice,
            ),
        }
    }
}

impl Emitter {
    /// Every map of unit-square sample `(s, t)`, in the order they are rasterized and shaded: the
    /// one `sample_map` for most kinds; for the point light the six cube faces (+x, −x, +y, −y,
    /// +z, −z), of which the lookup counts exactly one per receiver. Face f's map looks from
    /// `point_light_point(f, s, t)`: a point of the ball whose projection towards any receiver is,
    /// over the samples, the silhouette it sees (docs/lights.md, "Cube maps for the point");
    /// (½, ½) is the centre for every face.
    pub fn sample_maps(
        &self,
        light: &AreaLight,
        s: f32,
        t: f32,
        bounds: &Bounds,
        map_size: u32,
        lattice: u32,
    ) -> Vec<GpuSample> {
        match self {
            Emitter::Point(point) => (0..6u32)
                .map(|face| {
                    cube_face_view(
                        point.position,
                        point_light_point(point, face, s, t),
                        face,
                        bounds,
                        map_size,
                        lattice,
                    )
                })
                .collect(),
            _ => vec![self.sample_map(light, s, t, bounds, map_size, lattice)],
        }
    }
}

/// The cube face (0..5: +x, −x, +y, −y, +z, −z) whose axis dominates `d`, ties to the earlier
/// axis: the face that holds a receiver at `d` from the point light's centre. The kernels'
/// `cube_face` (kernels/shared/common.wgsl) is its GPU twin.
pub fn cube_face(d: Vec3) -> u32 {
    let a = d.abs();
    let x = a.x >= a.y && a.x >= a.z;
    let y = !x && a.y >= a.z;
    let (axis, along) = if x {
        (0, d.x)
    } else if y {
        (1, d.y)
    } else {
        (2, d.z)
    };
    axis * 2 + (along < 0.0) as u32
}

/// Face `face`'s light point for unit-square sample `(s, t)` of the point light: `c + r·(u·x + v·y +
/// a·z)`, (u, v) the two axes across the face's axis a, (x, y) the concentric map of (s, t) and
/// z = √(1 − x² − y²)·sin(π(w − ½)) a depth along a from the pseudo-random `w = ball_w(s, t)`.
/// Over the samples these points have the density 1/√(1 − |q|²) in the unit ball, whose projection
/// along every direction is the uniform disk: a receiver tilted from the face's axis sees, on
/// average, its whole silhouette, where the flat disk (z = 0) showed it foreshortened by the tilt's
/// cosine. A receiver on the axis sees the flat disk's points (docs/lights.md, "The light points").
pub fn point_light_point(point: &PointLight, face: u32, s: f32, t: f32) -> Vec3 {
    let (x, y) = concentric(s, t);
    let axes = [Vec3::X, Vec3::Y, Vec3::Z];
    let a = (face / 2) as usize;
    let (u, v, along) = (axes[(a + 1) % 3], axes[(a + 2) % 3], axes[a]);
    point.position + point.radius * (u * x + v * y + along * ball_depth(x, y, s, t))
}

/// The spot's light point for unit-square sample `(s, t)`: the point the concentric map sends it
/// to on the disk across `direction` (the stand-in square `light`, half-edges the radius), moved
/// along `direction` by `radius · ball_depth`: the point light's ball points (`point_light_point`)
/// with the cone's axis for the face's. A receiver off the axis sees, on average, the sphere's
/// whole silhouette, where the flat disk showed it foreshortened by the angle's cosine.
pub fn spot_light_point(light: &AreaLight, spot: &SpotLight, s: f32, t: f32) -> Vec3 {
    let (x, y) = concentric(s, t);
    light.point(0.5 + 0.5 * x, 0.5 + 0.5 * y)
        + spot.direction * (spot.radius * ball_depth(x, y, s, t))
}

/// The depth across the disk of a ball point over disk point (x, y) = concentric(s, t):
/// √(1 − x² − y²)·sin(π(w − ½)) with w = `ball_w(s, t)`, the arcsine law on the chord.
pub(crate) fn ball_depth(x: f32, y: f32, s: f32, t: f32) -> f32 {
    (1.0 - x * x - y * y).max(0.0).sqrt() * (std::f32::consts::PI * (ball_w(s, t) - 0.5)).sin()
}

/// The depth coordinate's uniform variate for sample `(s, t)`: ½ at the centre (the hard shadow's
/// point stays the sphere's centre), 1 − w at the point mirrored through it (the depths of a
/// symmetric grid cancel in pairs), otherwise spread by irrational slopes.
pub(crate) fn ball_w(s: f32, t: f32) -> f32 {
    let w = 0.5 + (s - 0.5) * 16.180_34 + (t - 0.5) * 14.142_136;
    w - w.floor()
}

/// Shirley and Chiu's concentric map: the unit square onto the unit disk, area-preserving, with
/// compact strata (a square's centre goes to the disk's centre).
pub fn concentric(s: f32, t: f32) -> (f32, f32) {
    let (a, b) = (2.0 * s - 1.0, 2.0 * t - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let q = std::f32::consts::FRAC_PI_4;
    let (r, phi) = if a.abs() > b.abs() {
        (a, q * (b / a))
    } else {
        (b, 2.0 * q - q * (a / b))
    };
    (r * phi.cos(), r * phi.sin())
}

/// Edges of a square of `side` whose `edge_u × edge_v` points along the unit `normal` (the `size`
/// form's rule: u along +x, or +z when the normal is close to x).
pub(crate) fn square_edges(normal: Vec3, side: f32) -> (Vec3, Vec3) {
    let hint = if normal.x.abs() < 0.9 {
        Vec3::X
    } else {
        Vec3::Z
    };
    let u = (hint - normal * hint.dot(normal)).normalize();
    (u * side, normal.cross(u) * side)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stand_ins_face_the_emitters_way_and_take_its_size() {
        let bounds = Bounds {
            min: Vec3::new(-5.0, 0.0, -5.0),
            max: Vec3::new(5.0, 2.0, 5.0),
        };
        let disk = Emitter::Disk(DiskLight {
            center: Vec3::new(0.0, 6.0, 0.0),
            normal: Vec3::NEG_Y,
            radius: 1.5,
        });
        let l = disk.stand_in(&bounds).unwrap();
        assert!(
            (l.normal() - Vec3::NEG_Y).length() < 1e-6 && (l.edge_u.length() - 3.0).abs() < 1e-6
        );
        let sun = Emitter::Sun(SunLight {
            direction: Vec3::new(0.0, -1.0, 0.0),
            angular_diameter_deg: 2.0,
        });
        let l = sun.stand_in(&bounds).unwrap();
        assert!(l.center.y > bounds.max.y && (l.normal() - Vec3::NEG_Y).length() < 1e-6);
        let point = Emitter::Point(PointLight {
            position: Vec3::new(3.0, 8.0, 0.0),
            radius: 0.5,
        });
        let l = point.stand_in(&bounds).unwrap();
        assert!(l.normal().dot(Vec3::new(0.0, 1.0, 0.0) - l.center) > 0.0);
        assert_eq!(Emitter::Rect.stand_in(&bounds), None);
    }

    #[test]
    fn the_cone_factor_is_one_inside_zero_outside_and_smooth_between() {
        let s = SpotLight {
            position: Vec3::ZERO,
            direction: Vec3::NEG_Y,
            inner_cone_deg: 20.0,
            outer_cone_deg: 40.0,
            radius: 0.1,
        };
        let at = |deg: f32| {
            s.cone_factor(Vec3::new(
                deg.to_radians().sin(),
                -deg.to_radians().cos(),
                0.0,
            ))
        };
        assert_eq!(at(0.0), 1.0);
        assert_eq!(at(19.9), 1.0);
        assert_eq!(at(40.1), 0.0);
        let mid = at(30.0);
        assert!(mid > 0.2 && mid < 0.8, "{mid}");
        assert!(at(25.0) > mid && mid > at(35.0));
    }

    #[test]
    fn the_point_lights_points_project_to_the_whole_disk_along_tilted_directions() {
        // A 64×64 grid on face 3 (−y). Seen along a direction tilted 50° from the face's axis the
        // unit disk's second moments are 1/4 across both axes; the flat disk (z = 0) would give
        // cos²50°/4 = 0.103 across the tilt.
        let light = PointLight {
            position: Vec3::new(1.0, 6.0, 0.5),
            radius: 1.5,
        };
        let n = 64;
        let pts: Vec<Vec3> = (0..n * n)
            .map(|k| {
                point_light_point(
                    &light,
                    3,
                    ((k % n) as f32 + 0.5) / n as f32,
                    ((k / n) as f32 + 0.5) / n as f32,
                )
            })
            .collect();
        assert!(
            pts.iter()
                .all(|p| (*p - light.position).length() <= light.radius * (1.0 + 1e-5)),
            "a point outside the sphere"
        );
        for tilt in [0.0f32, 30.0, 50.0] {
            let d = Vec3::new(0.0, -tilt.to_radians().cos(), tilt.to_radians().sin());
            let (e1, e2) = (Vec3::X, d.cross(Vec3::X).normalize());
            let m = |e: Vec3| {
                pts.iter()
                    .map(|p| ((*p - light.position).dot(e) / light.radius).powi(2))
                    .sum::<f32>()
                    / pts.len() as f32
            };
            assert!(
                (m(e1) - 0.25).abs() < 0.01 && (m(e2) - 0.25).abs() < 0.01,
                "tilt {tilt}: {} {}",
                m(e1),
                m(e2)
            );
        }
        // The centre is the sphere's centre; a mirrored pair has opposite depths.
        assert_eq!(point_light_point(&light, 0, 0.5, 0.5), light.position);
        let (a, b) = (
            point_light_point(&light, 3, 0.3, 0.8) - light.position,
            point_light_point(&light, 3, 0.7, 0.2) - light.position,
        );
        assert!((a + b).length() < 1e-4, "{a} {b}");
        assert_eq!(cube_face(Vec3::new(0.2, -3.0, 1.0)), 3);
    }

    #[test]
    fn the_spots_points_fill_its_ball_and_keep_the_disk_along_its_axis() {
        // The same moments as the point light's, about the cone's axis; along the axis each point
        // projects onto the flat disk the spot sampled before (the stand-in square's concentric point).
        let spot = SpotLight {
            position: Vec3::new(-1.0, 7.0, -0.5),
            direction: Vec3::new(0.2, -1.0, 0.0).normalize(),
            inner_cone_deg: 25.0,
            outer_cone_deg: 40.0,
            radius: 1.0,
        };
        let emitter = Emitter::Spot(spot);
        let light = emitter
            .stand_in(&Bounds {
                min: Vec3::splat(-10.0),
                max: Vec3::splat(10.0),
            })
            .unwrap();
        let n = 64;
        let st = |k: usize| {
            (
                ((k % n) as f32 + 0.5) / n as f32,
                ((k / n) as f32 + 0.5) / n as f32,
            )
        };
        let pts: Vec<Vec3> = (0..n * n)
            .map(|k| emitter.sample_point(&light, st(k).0, st(k).1) - spot.position)
            .collect();
        assert!(
            pts.iter().all(|q| q.length() <= spot.radius * (1.0 + 1e-5)),
            "a point outside the sphere"
        );
        for (k, q) in pts.iter().enumerate() {
            let (x, y) = concentric(st(k).0, st(k).1);
            let flat = light.point(0.5 + 0.5 * x, 0.5 + 0.5 * y) - spot.position;
            assert!(
                (*q - spot.direction * q.dot(spot.direction) - flat).length() < 1e-5,
                "sample {k}"
            );
        }
        let (u, v) = (light.edge_u.normalize(), light.edge_v.normalize());
        for tilt in [0.0f32, 30.0, 50.0] {
            let d = spot.direction * tilt.to_radians().cos() + v * tilt.to_radians().sin();
            let (e1, e2) = (u, d.cross(u).normalize());
            let m = |e: Vec3| {
                pts.iter()
                    .map(|q| (q.dot(e) / spot.radius).powi(2))
                    .sum::<f32>()
                    / pts.len() as f32
            };
            assert!(
                (m(e1) - 0.25).abs() < 0.01 && (m(e2) - 0.25).abs() < 0.01,
                "tilt {tilt}: {} {}",
                m(e1),
                m(e2)
            );
        }
        assert_eq!(emitter.sample_point(&light, 0.5, 0.5), spot.position);
        let (a, b) = (pts[10 * n + 20], pts[(n - 1 - 10) * n + (n - 1 - 20)]);
        assert!((a + b).length() < 1e-4, "{a} {b}");
    }
}
