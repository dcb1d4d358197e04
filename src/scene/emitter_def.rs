//! `[light]` by kind: which keys each kind takes, and the checks on each (docs/lights.md). A
//! rectangle is checked by `build_light`, as before kinds existed.

use super::coords::{finite, MAX_COORDINATE};
use super::emitter::{DiskLight, Emitter, LightKind, PointLight, SpotLight, SunLight};
use super::light::AreaLight;
use crate::{Error, Result};
use glam::Vec3;
use serde::Deserialize;

/// `kind` (default `rect`) and its keys (docs/lights.md). A rectangle is either `edge_u` + `edge_v`
/// (full edge vectors), or `size` + `normal` (+ optional `u_axis`); `emitter_def.rs` checks which
/// keys belong to which kind.
#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct LightDef {
    #[serde(default)]
    pub(crate) kind: LightKind,
    pub(crate) center: Option<[f32; 3]>,
    pub(crate) edge_u: Option<[f32; 3]>,
    pub(crate) edge_v: Option<[f32; 3]>,
    pub(crate) size: Option<[f32; 2]>,
    pub(crate) normal: Option<[f32; 3]>,
    pub(crate) u_axis: Option<[f32; 3]>,
    pub(crate) radius: Option<f32>,
    pub(crate) position: Option<[f32; 3]>,
    pub(crate) direction: Option<[f32; 3]>,
    pub(crate) angular_diameter_deg: Option<f32>,
    pub(crate) inner_cone_deg: Option<f32>,
    pub(crate) outer_cone_deg: Option<f32>,
}

/// The keys of each kind besides `kind` itself.
pub(crate) const KIND_KEYS: [(LightKind, &[&str]); 5] = [
    (
        LightKind::Rect,
        &["center", "edge_u", "edge_v", "size", "normal", "u_axis"],
    ),
    (LightKind::Disk, &["center", "normal", "radius"]),
    (LightKind::Sun, &["direction", "angular_diameter_deg"]),
    (
        LightKind::Spot,
        &[
            "position",
            "direction",
            "inner_cone_deg",
            "outer_cone_deg",
            "radius",
        ],
    ),
    (LightKind::Point, &["position", "radius"]),
];

/// The sun's angular diameter in degrees: above 0 (a sun of no size casts hard shadows; that is
/// `hard`'s job), at most 30 (ours is 0.53; wider is a sky, not a sun).
pub const MAX_SUN_DIAMETER_DEG: f32 = 30.0;
/// Cone half-angles stay below 90°: a spot is a cone, not a half-space (that is `point`).
pub(crate) const MAX_CONE_DEG: f32 = 90.0;

fn keys_of(kind: LightKind) -> &'static [&'static str] {
    KIND_KEYS
        .iter()
        .find(|(k, _)| *k == kind)
        .map_or(&[], |(_, keys)| *keys)
}

/// The keys the file gave, in [`KIND_KEYS`] order.
fn given(l: &LightDef) -> Vec<&'static str> {
    let present = [
        ("center", l.center.is_some()),
        ("edge_u", l.edge_u.is_some()),
        ("edge_v", l.edge_v.is_some()),
        ("size", l.size.is_some()),
        ("normal", l.normal.is_some()),
        ("u_axis", l.u_axis.is_some()),
        ("radius", l.radius.is_some()),
        ("position", l.position.is_some()),
        ("direction", l.direction.is_some()),
        ("angular_diameter_deg", l.angular_diameter_deg.is_some()),
        ("inner_cone_deg", l.inner_cone_deg.is_some()),
        ("outer_cone_deg", l.outer_cone_deg.is_some()),
    ];
    present
        .iter()
        .filter(|(_, p)| *p)
        .map(|(k, _)| *k)
        .collect()
}

/// The checked light: the rectangle (`Some`, with `Emitter::Rect`) or another kind's emitter.
pub(super) fn build(l: &LightDef, origin: &str) -> Result<(Option<AreaLight>, Emitter)> {
    let kind = l.kind;
    let keys = keys_of(kind);
    if let Some(stray) = given(l).into_iter().find(|k| !keys.contains(k)) {
        let owners: Vec<&str> = KIND_KEYS
            .iter()
            .filter(|(_, ks)| ks.contains(&stray))
            .map(|(k, _)| k.name())
            .collect();
        return Err(Error::scene(
            origin,
            format!(
                "light.{stray} is not a key of kind `{}` (its keys: {}); it belongs to kind {}",
                kind.name(),
                keys.join(", "),
                owners.join(", ")
            ),
        ));
    }
    let emitter = match kind {
        LightKind::Rect => return Ok((Some(build_light(l, origin)?), Emitter::Rect)),
        LightKind::Disk => Emitter::Disk(DiskLight {
            center: point(origin, kind, "center", l.center)?,
            normal: direction(origin, kind, "normal", l.normal)?,
            radius: radius(origin, kind, l.radius)?,
        }),
        LightKind::Sun => {
            let d = number(origin, kind, "angular_diameter_deg", l.angular_diameter_deg)?;
            if !(d > 0.0 && d <= MAX_SUN_DIAMETER_DEG) {
                return Err(Error::scene(
                    origin,
                    format!("light.angular_diameter_deg = {d}: must be in (0, {MAX_SUN_DIAMETER_DEG}] degrees (the sun is 0.53; a sun of no size is a hard shadow, wider is a sky)"),
                ));
            }
            Emitter::Sun(SunLight {
                direction: direction(origin, kind, "direction", l.direction)?,
                angular_diameter_deg: d,
            })
        }
        LightKind::Spot => {
            let position = point(origin, kind, "position", l.position)?;
            let dir = direction(origin, kind, "direction", l.direction)?;
            let inner = number(origin, kind, "inner_cone_deg", l.inner_cone_deg)?;
            let outer = number(origin, kind, "outer_cone_deg", l.outer_cone_deg)?;
            if !(0.0..MAX_CONE_DEG).contains(&inner) {
                return Err(Error::scene(origin, format!("light.inner_cone_deg = {inner}: must be in [0, {MAX_CONE_DEG}) degrees (a half-angle from the spot's direction)")));
            }
            if !(outer > 0.0 && outer < MAX_CONE_DEG) {
                return Err(Error::scene(origin, format!("light.outer_cone_deg = {outer}: must be in (0, {MAX_CONE_DEG}) degrees (a half-angle from the spot's direction)")));
            }
            if inner > outer {
                return Err(Error::scene(origin, format!("light.inner_cone_deg = {inner} is wider than light.outer_cone_deg = {outer}: the inner cone lies inside the outer one")));
            }
            Emitter::Spot(SpotLight {
                position,
                direction: dir,
                inner_cone_deg: inner,
                outer_cone_deg: outer,
                radius: radius(origin, kind, l.radius)?,
            })
        }
        LightKind::Point => Emitter::Point(PointLight {
            position: point(origin, kind, "position", l.position)?,
            radius: radius(origin, kind, l.radius)?,
        }),
    };
    Ok((None, emitter))
}

fn missing(origin: &str, kind: LightKind, key: &str) -> Error {
    Error::scene(
        origin,
        format!(
            "light.{key} is missing: kind `{}` needs {}",
            kind.name(),
            keys_of(kind).join(", ")
        ),
    )
}

fn point(origin: &str, kind: LightKind, key: &str, v: Option<[f32; 3]>) -> Result<Vec3> {
    finite(
        origin,
        &format!("light.{key}"),
        v.ok_or_else(|| missing(origin, kind, key))?,
    )
}

/// A unit vector from a finite, non-zero one.
fn direction(origin: &str, kind: LightKind, key: &str, v: Option<[f32; 3]>) -> Result<Vec3> {
    let d = point(origin, kind, key, v)?;
    let unit = d.normalize_or_zero();
    if unit == Vec3::ZERO {
        return Err(Error::scene(
            origin,
            format!(
                "light.{key} = {:?}: has no direction (the zero vector)",
                d.to_array()
            ),
        ));
    }
    Ok(unit)
}

fn number(origin: &str, kind: LightKind, key: &str, v: Option<f32>) -> Result<f32> {
    let x = v.ok_or_else(|| missing(origin, kind, key))?;
    if !x.is_finite() {
        return Err(Error::scene(
            origin,
            format!("light.{key} = {x}: must be a finite number"),
        ));
    }
    Ok(x)
}

/// An emitter's size: positive (a point of no size is a hard shadow) and within the coordinates.
fn radius(origin: &str, kind: LightKind, v: Option<f32>) -> Result<f32> {
    let r = number(origin, kind, "radius", v)?;
    if !(r > 0.0 && r <= MAX_COORDINATE) {
        return Err(Error::scene(origin, format!("light.radius = {r}: must be positive and at most {MAX_COORDINATE:e} (a soft shadow needs an emitter of some size)")));
    }
    Ok(r)
}

pub(super) fn build_light(l: &LightDef, origin: &str) -> Result<AreaLight> {
    let center = finite(origin, "light.center", l.center.ok_or_else(|| Error::scene(origin, "light.center is missing: kind `rect` needs center, and edge_u + edge_v or size + normal"))?)?;
    let (edge_u, edge_v) =
        match (l.edge_u, l.edge_v, l.size, l.normal) {
            (Some(u), Some(v), None, None) => (
                finite(origin, "light.edge_u", u)?,
                finite(origin, "light.edge_v", v)?,
            ),
            (None, None, Some(size), Some(normal)) => {
                let n = finite(origin, "light.normal", normal)?;
                if !(size[0] > 0.0 && size[1] > 0.0) {
                    return Err(Error::scene(
                        origin,
                        format!("light.size = {size:?}: both sides must be positive"),
                    ));
                }
                let size = finite(origin, "light.size", size)?;
                if n.length() < 1e-12 {
                    return Err(Error::scene(origin, "light.normal is the zero vector"));
                }
                let n = n.normalize();
                let hint = match l.u_axis {
                    Some(u) => finite(origin, "light.u_axis", u)?,
                    None if n.x.abs() < 0.9 => Vec3::X,
                    None => Vec3::Z,
                };
                let u = (hint - n * hint.dot(n)).normalize_or_zero();
                if u == Vec3::ZERO {
                    return Err(Error::scene(
                        origin,
                        "light.u_axis is parallel to light.normal",
                    ));
                }
                // Emission side is edge_u × edge_v, so v = n × u.
                (u * size.x, n.cross(u) * size.y)
            }
            _ => return Err(Error::scene(
                origin,
                "light: give either edge_u and edge_v, or size and normal (with optional u_axis)",
            )),
        };
    let light = AreaLight {
        center,
        edge_u,
        edge_v,
    };
    let scale = edge_u.length().max(edge_v.length()).max(1e-30);
    // Edges are within ±MAX_COORDINATE, so the area cannot overflow f32 here. Negated so that a NaN
    // area is refused too.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    let degenerate = !(light.edge_u.cross(light.edge_v).length() > 1e-10 * scale * scale);
    if degenerate {
        return Err(Error::scene(
            origin,
            format!("light has zero area (edge_u = {edge_u}, edge_v = {edge_v}): a soft shadow needs an area light"),
        ));
    }
    Ok(light)
}
