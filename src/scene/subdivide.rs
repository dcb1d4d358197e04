//! Subdivision: each triangle into four per level, to reach the seed's triangle counts (its scenes are
//! denser than the meshes the registries ship). Shared edges get one new vertex, so the mesh stays
//! watertight and no shadow-map texel leaks through a crack.
//! - `midpoint`: new vertices at edge midpoints, old ones kept: the surface is unchanged (facets too).
//! - `loop`: Loop's smooth scheme, the limit surface of a smooth model (a tessellated Bezier teapot
//!   has no flat facets; flat facets make whole facets half-lit at the terminator).

use super::raw_mesh::RawMesh;
use glam::Vec3;
use std::collections::HashMap;

/// Triangles one mesh may reach by subdivision (memory guard: 32M triangles ≈ 1.3 GB of vertices).
pub(crate) const MAX_TRIANGLES: u64 = 1 << 25;

#[derive(serde::Deserialize, Debug, Clone, Copy, Default, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub(crate) enum Scheme {
    #[default]
    Midpoint,
    Loop,
}

/// `levels` rounds of 1→4 splits; `Err` says why when the result would be too large.
pub(crate) fn subdivide(mesh: RawMesh, levels: u32, scheme: Scheme) -> Result<RawMesh, String> {
    let triangles = (mesh.indices.len() / 3) as u64;
    let after = triangles
        .checked_shl(2 * levels)
        .filter(|&t| levels < 16 && t <= MAX_TRIANGLES);
    if after.is_none() {
        return Err(format!(
            "subdivide = {levels} would turn {triangles} triangles into more than {MAX_TRIANGLES} (each level multiplies by 4)"
        ));
    }
    Ok((0..levels).fold(mesh, |m, _| match scheme {
        Scheme::Midpoint => once(m),
        Scheme::Loop => super::loop_subdivision::once(m),
    }))
}

fn once(mesh: RawMesh) -> RawMesh {
    let RawMesh {
        mut positions,
        mut normals,
        indices,
    } = mesh;
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::with_capacity(indices.len());
    let mut out = Vec::with_capacity(indices.len() * 4);
    let mut midpoint = |a: u32, b: u32| -> u32 {
        let key = (a.min(b), a.max(b));
        *midpoints.entry(key).or_insert_with(|| {
            let (pa, pb) = (positions[a as usize], positions[b as usize]);
            positions.push((pa + pb) * 0.5);
            if let Some(n) = normals.as_mut() {
                let m: Vec3 = (n[a as usize] + n[b as usize]).normalize_or_zero();
                n.push(m);
            }
            positions.len() as u32 - 1
        })
    };
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]];
        let (ab, bc, ca) = (midpoint(a, b), midpoint(b, c), midpoint(c, a));
        // Same winding as the parent in all four.
        out.extend([a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca]);
    }
    RawMesh {
        positions,
        normals,
        indices: out,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> RawMesh {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, 1.0), Vec3::Z];
        RawMesh {
            positions,
            normals: None,
            indices: vec![0, 2, 1, 0, 3, 2],
        }
    }

    #[test]
    fn four_times_the_triangles_shared_midpoints_same_area_and_winding() {
        let m = subdivide(quad(), 2, Scheme::Midpoint).unwrap();
        assert_eq!(m.indices.len() / 3, 2 * 16);
        // A 4x4 grid of quads has 5x5 vertices: every shared edge got exactly one midpoint.
        assert_eq!(m.positions.len(), 25);
        let mut area = 0.0;
        for t in m.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.y > 0.0, "winding flipped");
            area += n.length() / 2.0;
        }
        assert!((area - 1.0).abs() < 1e-6);
    }

    #[test]
    fn refuses_a_result_too_large() {
        let e = subdivide(quad(), 13, Scheme::Loop).err().unwrap();
        assert!(e.contains("subdivide = 13"), "{e}");
    }
}
