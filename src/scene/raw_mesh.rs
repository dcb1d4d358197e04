//! A mesh as loaded or built, before placement: what every mesh reader and subdivider passes on.

use glam::Vec3;

/// Positions + triangle indices in object space; normals are derived after the transform.
#[derive(Debug)]
pub(crate) struct RawMesh {
    pub(crate) positions: Vec<Vec3>,
    pub(crate) normals: Option<Vec<Vec3>>,
    pub(crate) indices: Vec<u32>,
}

impl RawMesh {
    /// Edges used by one triangle only, in one direction (vertices welded by their exact position,
    /// so a file's seam copies count as one): 0 for a closed, consistently wound mesh. Culling back
    /// faces in the shadow raster is exact only then (docs/scene-format.md).
    pub(crate) fn boundary_edges(&self) -> usize {
        use std::collections::{HashMap, HashSet};
        let mut weld: HashMap<[u32; 3], u32> = HashMap::with_capacity(self.positions.len());
        let id: Vec<u32> = self
            .positions
            .iter()
            .map(|p| {
                let next = weld.len() as u32;
                *weld.entry(p.to_array().map(f32::to_bits)).or_insert(next)
            })
            .collect();
        let edges: HashSet<(u32, u32)> = self
            .indices
            .chunks_exact(3)
            .flat_map(|t| {
                let [a, b, c] = [t[0], t[1], t[2]].map(|i| id[i as usize]);
                [(a, b), (b, c), (c, a)]
            })
            .collect();
        edges
            .iter()
            .filter(|&&(a, b)| !edges.contains(&(b, a)))
            .count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closed_tetrahedron_has_no_boundary_and_a_square_four_edges() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let closed = RawMesh {
            positions: p.clone(),
            normals: None,
            indices: vec![0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3],
        };
        assert_eq!(closed.boundary_edges(), 0);
        // Two triangles of a square, its shared edge split into two vertex copies: welded, the
        // diagonal is inner and the four sides are the boundary.
        let square = RawMesh {
            positions: vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::ZERO,
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::Y,
            ],
            normals: None,
            indices: vec![0, 1, 2, 3, 4, 5],
        };
        assert_eq!(square.boundary_edges(), 4);
        // One face of the tetrahedron removed: its three edges open.
        let open = RawMesh {
            positions: p,
            normals: None,
            indices: vec![0, 2, 1, 0, 1, 3, 0, 3, 2],
        };
        assert_eq!(open.boundary_edges(), 3);
    }
}
