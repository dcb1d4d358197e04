//! Scene meshes: built-in primitives (plane, box, sphere) and mesh files, placed by a transform and
//! optionally subdivided and instanced.

use super::coords::MAX_COORDINATE;
use super::mesh_def::{MeshDef, Scale};
use super::mesh_file::{self, MeshDirs};
use super::raw_mesh::RawMesh;
use super::{instances, subdivide};
use crate::{Error, Result};
use bytemuck::{Pod, Zeroable};
use glam::{EulerRot, Mat3, Mat4, Quat, Vec3};

/// Vertex as the G-buffer and shadow raster read it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub material: u32,
}

/// Loads (or builds) one `[[mesh]]`, subdivides it, applies its transform, then places one copy per
/// instance. Normals are computed once and turned with each placement. Also returns a mesh file's
/// boundary edges as loaded (0 for the built-ins: the plane is open by design).
pub(crate) fn instantiate(
    m: &MeshDef,
    k: usize,
    origin: &str,
    dirs: MeshDirs,
) -> Result<(Vec<Vertex>, Vec<u32>, usize)> {
    let label = format!("{origin}: mesh {}", k + 1);
    if m.builtin.as_deref() == Some("sphere") && !(3..=512).contains(&m.segments) {
        return Err(Error::scene(
            origin,
            format!(
                "mesh {}: segments = {} for a sphere: must be in 3..=512",
                k + 1,
                m.segments
            ),
        ));
    }
    let raw = match (&m.builtin, &m.file) {
        (Some(b), None) => builtin(b, m.segments).ok_or_else(|| {
            Error::scene(
                origin,
                format!("mesh {}: unknown builtin `{b}` (plane, box, sphere)", k + 1),
            )
        })?,
        (None, Some(f)) => mesh_file::load(f, origin, &format!("mesh {}", k + 1), dirs)?,
        _ => {
            return Err(Error::scene(
                origin,
                format!("mesh {}: give exactly one of `builtin` or `file`", k + 1),
            ))
        }
    };
    if raw.indices.is_empty() {
        return Err(Error::mesh(label, "the mesh is empty (no triangles)"));
    }
    let open_edges = if m.file.is_some() {
        raw.boundary_edges()
    } else {
        0
    };
    let raw = subdivide::subdivide(raw, m.subdivide, m.subdivision)
        .map_err(|e| Error::scene(origin, format!("mesh {}: {e}", k + 1)))?;
    let placements = instances::placements(m)
        .map_err(|e| Error::scene(origin, format!("mesh {}: {e}", k + 1)))?;
    let scale = match m.scale {
        Scale::Uniform(s) => Vec3::splat(s),
        Scale::Axes(a) => Vec3::from(a),
    };
    check_transform(m, k, origin)?;
    let copies = placements.len() as u64;
    if (raw.positions.len() as u64) * copies > u32::MAX as u64
        || (raw.indices.len() as u64 / 3) * copies > MAX_SCENE_TRIANGLES
    {
        return Err(Error::scene(
            origin,
            format!("mesh {}: {copies} instances of {} triangles exceed {MAX_SCENE_TRIANGLES} triangles", k + 1, raw.indices.len() / 3),
        ));
    }
    let r = m.rotate_deg.map(f32::to_radians);
    let rotation = Quat::from_euler(EulerRot::XYZ, r[0], r[1], r[2]);
    let world = Mat4::from_scale_rotation_translation(scale, rotation, Vec3::from(m.translate));
    let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
    let positions: Vec<Vec3> = raw
        .positions
        .iter()
        .map(|p| world.transform_point3(*p))
        .collect();
    let normals = match &raw.normals {
        Some(n) => n
            .iter()
            .map(|n| (normal_matrix * *n).normalize_or_zero())
            .collect(),
        None => smooth_normals(&positions, &raw.indices),
    };
    let mut vertices: Vec<Vertex> = Vec::with_capacity(positions.len() * placements.len());
    let mut indices = Vec::with_capacity(raw.indices.len() * placements.len());
    for place in &placements {
        // Placements are rotation + positive uniform scale: the rotation alone turns normals.
        let turn = Mat3::from_mat4(*place);
        let base = vertices.len() as u32;
        vertices.extend(positions.iter().zip(&normals).map(|(p, n)| Vertex {
            position: place.transform_point3(*p).to_array(),
            normal: (turn * *n).normalize_or_zero().to_array(),
            material: 0,
        }));
        indices.extend(raw.indices.iter().map(|i| i + base));
    }
    // Each factor is bounded, but together (a big mesh file, scale 1e6, instances far out) they can
    // still leave f32's useful range: the placed vertices obey the scene file's coordinate bound.
    if let Some(v) = vertices
        .iter()
        .find(|v| !v.position.iter().all(|x| x.abs() <= MAX_COORDINATE))
    {
        return Err(Error::scene(
            origin,
            format!("mesh {}: a placed vertex lands at {:?}, beyond ±{MAX_COORDINATE:e}: shrink translate, scale or the instances", k + 1, v.position),
        ));
    }
    Ok((vertices, indices, open_edges))
}

/// Scale factors per axis, by size (0 flattens the mesh; beyond 1e6 f32 loses it).
pub(crate) const SCALE_RANGE: [f32; 2] = [1e-6, 1e6];
/// `rotate_deg` per axis: ten turns; larger angles are typos, and lose precision in f32.
pub(crate) const MAX_ROTATE_DEG: f32 = 3600.0;

/// The `[[mesh]]` transform: every message names the mesh, the key and its value.
fn check_transform(m: &MeshDef, k: usize, origin: &str) -> Result<()> {
    let fail = |msg: String| Err(Error::scene(origin, format!("mesh {}: {msg}", k + 1)));
    let scale_text = match m.scale {
        Scale::Uniform(s) => format!("{s:?}"),
        Scale::Axes(a) => format!("{a:?}"),
    };
    let scale = match m.scale {
        Scale::Uniform(s) => [s; 3],
        Scale::Axes(a) => a,
    };
    let keys: [(&str, String, [f32; 3]); 3] = [
        ("translate", format!("{:?}", m.translate), m.translate),
        ("rotate_deg", format!("{:?}", m.rotate_deg), m.rotate_deg),
        ("scale", scale_text.clone(), scale),
    ];
    if let Some((key, text, _)) = keys
        .iter()
        .find(|(_, _, v)| v.iter().any(|x| !x.is_finite()))
    {
        return fail(format!("{key} = {text}: has a NaN or infinite number"));
    }
    if m.translate.iter().any(|x| x.abs() > MAX_COORDINATE) {
        return fail(format!("translate = {:?}: each component must be within ±{MAX_COORDINATE:e} (f32 has no precision left beyond)", m.translate));
    }
    if m.rotate_deg.iter().any(|x| x.abs() > MAX_ROTATE_DEG) {
        return fail(format!(
            "rotate_deg = {:?}: each angle must be within ±{MAX_ROTATE_DEG} degrees",
            m.rotate_deg
        ));
    }
    let [lo, hi] = SCALE_RANGE;
    if scale.iter().any(|x| !(lo..=hi).contains(&x.abs())) {
        return fail(format!(
            "scale = {scale_text}: each factor's size must be within [{lo:e}, {hi:e}]"
        ));
    }
    Ok(())
}

/// Triangles a scene may hold after instancing and subdivision (64M: 4 GB of vertices and indices).
pub(crate) const MAX_SCENE_TRIANGLES: u64 = 1 << 26;

/// Area-weighted vertex normals (the cross product's length is twice the area).
pub(super) fn smooth_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut n = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| positions[t[k] as usize]);
        let face = (b - a).cross(c - a);
        for k in 0..3 {
            n[t[k] as usize] += face;
        }
    }
    n.into_iter().map(|v| v.normalize_or_zero()).collect()
}

fn builtin(name: &str, segments: u32) -> Option<RawMesh> {
    match name {
        "plane" => Some(plane()),
        "box" => Some(cube()),
        "sphere" => Some(sphere(segments)),
        _ => None,
    }
}

/// Unit square in the xz plane at y = 0, facing +y, counter-clockwise seen from above.
fn plane() -> RawMesh {
    let positions = vec![
        Vec3::new(-0.5, 0.0, 0.5),
        Vec3::new(0.5, 0.0, 0.5),
        Vec3::new(0.5, 0.0, -0.5),
        Vec3::new(-0.5, 0.0, -0.5),
    ];
    RawMesh {
        normals: Some(vec![Vec3::Y; 4]),
        positions,
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

/// Unit cube centred at the origin, flat-shaded faces.
fn cube() -> RawMesh {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut indices = Vec::new();
    for axis in [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ] {
        let u = if axis.y.abs() > 0.5 { Vec3::X } else { Vec3::Y };
        let v = axis.cross(u);
        let base = positions.len() as u32;
        for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            positions.push(0.5 * (axis + a * u + b * v));
            normals.push(axis);
        }
        // counter-clockwise seen from outside: (u × v) must point along the axis
        if u.cross(v).dot(axis) > 0.0 {
            indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        } else {
            indices.extend([base, base + 2, base + 1, base, base + 3, base + 2]);
        }
    }
    RawMesh {
        positions,
        normals: Some(normals),
        indices,
    }
}

/// Unit-radius UV sphere, outward counter-clockwise.
fn sphere(segments: u32) -> RawMesh {
    let rings = segments.max(2);
    let mut positions = Vec::new();
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = 2.0 * std::f32::consts::PI * s as f32 / segments as f32;
            positions.push(Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ));
        }
    }
    let row = segments + 1;
    let mut indices = Vec::new();
    for r in 0..rings {
        for s in 0..segments {
            let a = r * row + s;
            let (b, c, d) = (a + 1, a + row, a + row + 1);
            if r != 0 {
                indices.extend([a, b, c]);
            }
            if r + 1 != rings {
                indices.extend([b, d, c]);
            }
        }
    }
    let normals = positions.clone();
    RawMesh {
        positions,
        normals: Some(normals),
        indices,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outward(m: &RawMesh) -> bool {
        m.indices.chunks_exact(3).all(|t| {
            let [a, b, c] = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
            let centroid = (a + b + c) / 3.0;
            (b - a).cross(c - a).dot(centroid) > 0.0
        })
    }

    #[test]
    fn builtins_wind_counter_clockwise_outward() {
        assert!(outward(&cube()));
        assert!(outward(&sphere(16)));
        let p = plane();
        let [a, b, c] = [0, 1, 2].map(|k| p.positions[p.indices[k] as usize]);
        assert!((b - a).cross(c - a).y > 0.0);
        assert_eq!(cube().indices.len(), 36);
    }
}
