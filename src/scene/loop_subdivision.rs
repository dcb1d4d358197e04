//! One level of Loop subdivision (Loop 1987, with Warren's weights): smooth where the mesh is a
//! closed 2-manifold, boundary edges (and non-manifold ones) kept as creases with the cubic B-spline
//! curve rule, so both sides of an open seam land on the same points and no crack opens.

use super::raw_mesh::RawMesh;
use glam::Vec3;
use std::collections::HashMap;

struct Edge {
    /// The vertex opposite the edge in each face that has it (a manifold interior edge has two).
    opposite: Vec<u32>,
    new_vertex: u32,
}

pub(crate) fn once(mesh: RawMesh) -> RawMesh {
    let (positions, triangles) = weld(&mesh);
    let n = positions.len();
    let mut edges: HashMap<(u32, u32), Edge> = HashMap::with_capacity(triangles.len() * 2);
    for t in &triangles {
        for k in 0..3 {
            let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            edges
                .entry((a.min(b), a.max(b)))
                .or_insert_with(|| Edge {
                    opposite: Vec::new(),
                    new_vertex: 0,
                })
                .opposite
                .push(c);
        }
    }
    // Sorted so vertex order and every float sum (hence the output's bits, and the reference
    // cache keys made from them) do not depend on the hash map's per-process iteration order.
    let mut keys: Vec<(u32, u32)> = edges.keys().copied().collect();
    keys.sort_unstable();
    let mut neighbours = vec![Vec::new(); n];
    let mut crease_neighbours = vec![Vec::new(); n];
    for &(a, b) in &keys {
        let e = &edges[&(a, b)];
        neighbours[a as usize].push(b);
        neighbours[b as usize].push(a);
        if e.opposite.len() != 2 {
            crease_neighbours[a as usize].push(b);
            crease_neighbours[b as usize].push(a);
        }
    }
    let p = |i: u32| positions[i as usize];
    let mut out: Vec<Vec3> = (0..n)
        .map(|v| {
            let here = positions[v];
            match crease_neighbours[v].as_slice() {
                [] => {
                    let k = neighbours[v].len() as f32;
                    let beta = if neighbours[v].len() == 3 {
                        3.0 / 16.0
                    } else {
                        3.0 / (8.0 * k)
                    };
                    here * (1.0 - k * beta)
                        + neighbours[v].iter().map(|&u| p(u)).sum::<Vec3>() * beta
                }
                [a, b] => here * 0.75 + (p(*a) + p(*b)) * 0.125,
                // A corner where creases meet, or a non-manifold vertex: keep it in place.
                _ => here,
            }
        })
        .collect();
    for key in keys {
        let e = edges.get_mut(&key).expect("key from the map");
        let (a, b) = (p(key.0), p(key.1));
        let point = match e.opposite.as_slice() {
            [c, d] => (a + b) * 0.375 + (p(*c) + p(*d)) * 0.125,
            _ => (a + b) * 0.5,
        };
        e.new_vertex = out.len() as u32;
        out.push(point);
    }
    let mid = |a: u32, b: u32| edges[&(a.min(b), a.max(b))].new_vertex;
    let mut indices = Vec::with_capacity(triangles.len() * 12);
    for &[a, b, c] in &triangles {
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        indices.extend([a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca]);
    }
    RawMesh {
        positions: out,
        normals: None,
        indices,
    }
}

/// Merges vertices at bit-identical positions (files split them at normal or texture seams, which
/// would turn every seam into a crease) and drops the triangles that collapse.
fn weld(mesh: &RawMesh) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut first: HashMap<[u32; 3], u32> = HashMap::with_capacity(mesh.positions.len());
    let mut positions = Vec::with_capacity(mesh.positions.len());
    let remap: Vec<u32> = mesh
        .positions
        .iter()
        .map(|p| {
            *first
                .entry(p.to_array().map(f32::to_bits))
                .or_insert_with(|| {
                    positions.push(*p);
                    positions.len() as u32 - 1
                })
        })
        .collect();
    let triangles = mesh
        .indices
        .chunks_exact(3)
        .map(|t| {
            [
                remap[t[0] as usize],
                remap[t[1] as usize],
                remap[t[2] as usize],
            ]
        })
        .filter(|[a, b, c]| a != b && b != c && c != a)
        .collect();
    (positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn octahedron() -> RawMesh {
        let positions = vec![
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::Z,
            Vec3::NEG_Z,
        ];
        let indices = vec![
            0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5,
        ];
        RawMesh {
            positions,
            normals: None,
            indices,
        }
    }

    #[test]
    fn output_bits_do_not_depend_on_hash_order() {
        // Every map gets its own random hash keys: repeated runs must still agree bit for bit.
        let bits = |m: &RawMesh| {
            m.positions
                .iter()
                .flat_map(|p| p.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        let first = once(once(octahedron()));
        for _ in 0..8 {
            let again = once(once(octahedron()));
            assert_eq!(bits(&again), bits(&first));
            assert_eq!(again.indices, first.indices);
        }
    }

    #[test]
    fn closed_mesh_stays_closed_and_shrinks_towards_a_smooth_surface() {
        let m = once(octahedron());
        assert_eq!(m.indices.len() / 3, 32);
        // Euler characteristic of a sphere: V - E + F = 2 with E = 3F/2.
        assert_eq!(m.positions.len(), 2 + 32 / 2);
        // Loop is approximating: a degree-4 vertex keeps 1 - 4·3/32 of itself and its four
        // neighbours (±Y, ±Z) sum to zero, so the radius goes from 1 to 0.625.
        assert!((m.positions[0] - Vec3::X * 0.625).length() < 1e-6);
    }

    #[test]
    fn open_square_keeps_its_boundary_straight() {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, 1.0), Vec3::Z];
        let m = once(RawMesh {
            positions,
            normals: None,
            indices: vec![0, 2, 1, 0, 3, 2],
        });
        assert!(m.positions.iter().all(|p| p.y == 0.0));
        // Corner vertices have two crease neighbours: 3/4 corner + 1/8 each neighbour.
        assert!((m.positions[0] - Vec3::new(0.125, 0.0, 0.125)).length() < 1e-6);
    }

    #[test]
    fn seams_are_welded() {
        let mut m = octahedron();
        // Split vertex 0 into a copy used by the faces below the equator.
        m.positions.push(Vec3::X);
        for i in 12..24 {
            if m.indices[i] == 0 {
                m.indices[i] = 6;
            }
        }
        let welded = once(m);
        assert_eq!(welded.positions.len(), 18);
    }
}
