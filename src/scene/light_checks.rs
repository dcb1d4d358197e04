//! Every check of a light against the scene it lights, in one place: the scene file's light when
//! it loads (`format::assemble`) and each frame's moved light in `sequence`. Each refuses a light
//! that would make the figures meaningless, up front, with one line naming the file, the key and
//! the value (docs/lights.md §1):
//!
//! - a rectangle, disk or spot that emits away from every mesh: nothing is lit;
//! - a sun that shines upward or along the horizon: no surface that faces up is lit;
//! - a point's or spot's sphere around the camera, or reaching into a mesh: points inside the
//!   emitter are unlit (the reference says V = 0 there), so the figures would measure the sphere;
//! - a light more than [`MAX_LIGHT_DIAGONALS`] × the scene's diagonal across: a sky, not a light;
//! - a rectangle, disk or spot so wide seen from the scene that the maps from its outer points,
//!   at most `MAX_TAN_HALF` wide in tangent, no longer see the scene's middle ([`check_field`]).

use super::emitter::Emitter;
use super::light::{tangents_seen, AreaLight, Bounds, MAX_TAN_HALF};
use super::mesh::Vertex;
use super::model::Scene;
use crate::{Error, Result};
use glam::Vec3;

/// A light may be at most this many times the diagonal of the meshes' bounding box across. The
/// shipped scenes' lights are at most 0.46 of it (`pole-between-corners`' 4 × 4 rectangle); at ten
/// diagonals the light is a sky over the scene: every penumbra spans the scene, and the shadow
/// maps, whose frusta are fitted to the scene and at most 2·atan(6) ≈ 161° wide, no longer see it
/// from the light's outer points (a disk of radius 1e6 over a 30-unit scene gave RMSE 0.87 to 1.00).
pub const MAX_LIGHT_DIAGONALS: f32 = 10.0;

/// What a light is checked against: the meshes (placed, as one list), their bounds and the eye.
pub(crate) struct Lit<'a> {
    pub(crate) bounds: &'a Bounds,
    pub(crate) eye: Vec3,
    pub(crate) vertices: &'a [Vertex],
    pub(crate) indices: &'a [u32],
}

/// All checks of the scene's light (`light` is the rectangle, or the stand-in of another kind).
pub(crate) fn check(origin: &str, light: &AreaLight, emitter: &Emitter, lit: &Lit) -> Result<()> {
    check_side(origin, light, emitter, lit.bounds)?;
    check_sun(origin, emitter)?;
    check_sphere(origin, emitter, lit)?;
    check_extent(origin, light, emitter, lit.bounds)?;
    check_field(origin, light, emitter, lit.bounds)
}

/// [`check`] on a built scene (a sequence's frame); an environment's nominal light lights nothing.
pub fn check_scene(scene: &Scene) -> Result<()> {
    if scene.environment.is_some() {
        return Ok(());
    }
    let lit = Lit {
        bounds: &scene.bounds,
        eye: scene.camera.eye,
        vertices: &scene.vertices,
        indices: &scene.indices,
    };
    check(&scene.origin, &scene.light, &scene.emitter, &lit)
}

/// With every mesh behind the emitting side, V = 0 everywhere.
fn check_side(origin: &str, light: &AreaLight, emitter: &Emitter, bounds: &Bounds) -> Result<()> {
    let (at, along, what) = match emitter {
        Emitter::Rect => (light.center, light.normal(), None),
        Emitter::Disk(d) => (
            d.center,
            d.normal,
            Some("the disk emits along light.normal"),
        ),
        Emitter::Spot(s) => (
            s.position,
            s.direction,
            Some("the spot points along light.direction"),
        ),
        Emitter::Sun(_) | Emitter::Point(_) => return Ok(()),
    };
    if bounds
        .corners()
        .iter()
        .map(|c| (*c - at).dot(along))
        .fold(f32::NEG_INFINITY, f32::max)
        > 0.0
    {
        return Ok(());
    }
    Err(Error::scene(
        origin,
        match what {
            None => format!(
                "light: emits along {:?} (edge_u × edge_v, or `normal`), away from every mesh: nothing would be lit; flip `normal` or swap edge_u and edge_v",
                along.to_array()
            ),
            Some(what) => format!("light: {what} = {:?}, away from every mesh: nothing would be lit; turn it towards the meshes", along.to_array()),
        },
    ))
}

/// The sun's `direction` is the way its light travels (docs/lights.md §1), and +y is up (the
/// `plane` mesh lies in xz): a direction with y ≥ 0 comes from at or below the horizon.
fn check_sun(origin: &str, emitter: &Emitter) -> Result<()> {
    let Emitter::Sun(sun) = emitter else {
        return Ok(());
    };
    if sun.direction.y < 0.0 {
        return Ok(());
    }
    Err(Error::scene(
        origin,
        format!(
            "light.direction = {:?}: the sun shines {} (direction is the way its light travels, from the sun to the scene, and +y is up): no surface that faces up would be lit; give it a negative y, e.g. [0.3, -1.0, 0.2]",
            sun.direction.to_array(),
            if sun.direction.y > 0.0 { "upward" } else { "along the horizon" }
        ),
    ))
}

/// A point's or spot's emitter sphere must hold neither the camera nor any part of a mesh.
fn check_sphere(origin: &str, emitter: &Emitter, lit: &Lit) -> Result<()> {
    let (at, radius) = match emitter {
        Emitter::Point(p) => (p.position, p.radius),
        Emitter::Spot(s) => (s.position, s.radius),
        _ => return Ok(()),
    };
    let given = format!(
        "light.position = {:?}, light.radius = {radius}",
        at.to_array()
    );
    let eye = (lit.eye - at).length();
    if eye <= radius {
        return Err(Error::scene(
            origin,
            format!(
                "{given}: the emitter's sphere encloses the camera (camera.eye = {:?} is {eye} from its centre): the camera would look out from inside the light; move light.position away or shrink light.radius",
                lit.eye.to_array()
            ),
        ));
    }
    if let Some((mesh, d)) = nearest_inside(at, radius, lit.vertices, lit.indices) {
        return Err(Error::scene(
            origin,
            format!(
                "{given}: the emitter's sphere reaches into mesh {} (a triangle of it is {d} from the centre): points inside the emitter are unlit, so the figures would measure the sphere, not the shadows; move light.position clear of the meshes or shrink light.radius",
                mesh + 1
            ),
        ));
    }
    Ok(())
}

/// The mesh (0-based) of the triangle nearest `at` and its distance, when it is under `radius`.
fn nearest_inside(
    at: Vec3,
    radius: f32,
    vertices: &[Vertex],
    indices: &[u32],
) -> Option<(u32, f32)> {
    let mut best: Option<(u32, f32)> = None;
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| Vec3::from(vertices[i as usize].position));
        // Cheap rejection first: the sphere misses the triangle's box.
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        if (at.clamp(lo, hi) - at).length() >= radius {
            continue;
        }
        let d = (closest_on_triangle(at, a, b, c) - at).length();
        if d < radius && best.is_none_or(|(_, b)| d < b) {
            best = Some((vertices[t[0] as usize].material, d));
        }
    }
    best
}

/// The point of triangle abc nearest p (Ericson, Real-Time Collision Detection §5.1.5).
fn closest_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = va + vb + vc;
    if denom.abs() < f32::MIN_POSITIVE {
        return a; // degenerate triangle: its vertices are as near as it gets
    }
    a + ab * (vb / denom) + ac * (vc / denom)
}

/// The light's size across: the rectangle's diagonal, the disk's or sphere's diameter. The sun is
/// at infinity: its size is an angle, bounded on its own (`MAX_SUN_DIAMETER_DEG`).
fn check_extent(origin: &str, light: &AreaLight, emitter: &Emitter, bounds: &Bounds) -> Result<()> {
    let (across, given) = match emitter {
        Emitter::Rect => (
            (light.edge_u.length_squared() + light.edge_v.length_squared()).sqrt(),
            format!(
                "light.edge_u = {:?}, light.edge_v = {:?} (or light.size)",
                light.edge_u.to_array(),
                light.edge_v.to_array()
            ),
        ),
        Emitter::Disk(d) => (2.0 * d.radius, format!("light.radius = {}", d.radius)),
        Emitter::Spot(s) => (2.0 * s.radius, format!("light.radius = {}", s.radius)),
        Emitter::Point(p) => (2.0 * p.radius, format!("light.radius = {}", p.radius)),
        Emitter::Sun(_) => return Ok(()),
    };
    let diagonal = bounds.diagonal();
    let limit = MAX_LIGHT_DIAGONALS * diagonal;
    if across <= limit {
        return Ok(());
    }
    Err(Error::scene(
        origin,
        format!(
            "{given}: the light is {} across, over {MAX_LIGHT_DIAGONALS} × the meshes' diagonal of {diagonal:.3} ({limit:.3}): it would light the scene as a sky, which the shadow maps fitted to the scene cannot see; shrink it (a light far away is kind = \"sun\")",
            // Plain digits while they read well; a disk of radius 1e6 reads as 2e6, not 2000000.000.
            if across >= 1e5 { format!("{across:e}") } else { format!("{across:.3}") }
        ),
    ))
}

/// Points around the emitter's outline, where the maps look from farthest out: the rectangle's
/// corners, or 64 points on the disk's (the spot's sphere's) rim, as `Emitter::sample_point` places
/// the outer samples on the stand-in square.
fn outline(light: &AreaLight, emitter: &Emitter) -> Vec<Vec3> {
    match emitter {
        Emitter::Rect => vec![
            light.point(0.0, 0.0),
            light.point(1.0, 0.0),
            light.point(0.0, 1.0),
            light.point(1.0, 1.0),
        ],
        _ => (0..64)
            .map(|k| {
                let a = k as f32 * std::f32::consts::TAU / 64.0;
                light.point(0.5 + 0.5 * a.cos(), 0.5 + 0.5 * a.sin())
            })
            .collect(),
    }
}

/// What breaks a light's maps is its angular size seen from the scene, not its size against the
/// scene: each map looks from a point of the emitter along its normal, its window fitted to the
/// scene but at most `MAX_TAN_HALF` (6, about 80.5°) from the normal across each axis, and what
/// lies beyond counts as unoccluded. A light wide and low enough that its outline, seen from the
/// middle of the meshes' bounds, reaches past that angle has maps that do not see the scene's
/// middle: a disk of radius 200 at height 8 over a 53-unit scene gave `regular:n=3` an RMSE of
/// 0.865 against hard's 0.11, within the 10-diagonal bound. The sun's maps are orthographic, and
/// the point's are cube faces that see every way: neither has the limit.
pub(crate) fn check_field(
    origin: &str,
    light: &AreaLight,
    emitter: &Emitter,
    bounds: &Bounds,
) -> Result<()> {
    let given = match emitter {
        Emitter::Rect => format!(
            "light.edge_u = {:?}, light.edge_v = {:?} (or light.size)",
            light.edge_u.to_array(),
            light.edge_v.to_array()
        ),
        Emitter::Disk(d) => format!(
            "light.center = {:?}, light.radius = {}",
            d.center.to_array(),
            d.radius
        ),
        Emitter::Spot(s) => format!(
            "light.position = {:?}, light.radius = {}",
            s.position.to_array(),
            s.radius
        ),
        Emitter::Sun(_) | Emitter::Point(_) => return Ok(()),
    };
    let middle = bounds.min.lerp(bounds.max, 0.5);
    // A middle at or behind the light's plane: the light lights the scene from inside it (a lamp
    // in a room); the side check has seen that some mesh is lit.
    if tangents_seen(light, light.center, middle).is_none() {
        return Ok(());
    }
    let worst = outline(light, emitter)
        .into_iter()
        .map(|y| {
            tangents_seen(light, y, middle).map_or(f32::INFINITY, |(u, v)| u.abs().max(v.abs()))
        })
        .fold(0.0f32, f32::max);
    if worst <= MAX_TAN_HALF {
        return Ok(());
    }
    Err(Error::scene(
        origin,
        format!(
            "{given}: seen from the middle of the meshes' bounds ({:?}) the light reaches {:.1}° from its normal (tangent {}), past the {:.1}° (tangent {MAX_TAN_HALF}) its shadow maps see from each of its points: the maps from its outer part would not see the scene; make it smaller or move it farther from the meshes",
            middle.to_array(),
            worst.atan().to_degrees(),
            if worst.is_finite() { format!("{worst:.2}") } else { "beyond 90°".into() },
            MAX_TAN_HALF.atan().to_degrees()
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_point_on_a_triangle_in_each_region() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let at = |p: Vec3| closest_on_triangle(p, a, b, c);
        assert_eq!(at(Vec3::new(0.25, 0.25, 3.0)), Vec3::new(0.25, 0.25, 0.0)); // face
        assert_eq!(at(Vec3::new(-1.0, -1.0, 0.0)), a);
        assert_eq!(at(Vec3::new(2.0, -0.5, 0.0)), b);
        assert_eq!(at(Vec3::new(-0.5, 2.0, 0.0)), c);
        assert_eq!(at(Vec3::new(0.5, -1.0, 1.0)), Vec3::new(0.5, 0.0, 0.0)); // edge ab
        assert_eq!(at(Vec3::new(-1.0, 0.5, 0.0)), Vec3::new(0.0, 0.5, 0.0)); // edge ac
        assert!((at(Vec3::new(1.0, 1.0, 0.0)) - Vec3::new(0.5, 0.5, 0.0)).length() < 1e-6);
        // edge bc
    }
}
