//! The loaded mesh and the one place where every loader's output is validated.

/// A triangle mesh: `indices` holds three entries per triangle, each `< positions.len()`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LoadedMesh {
    pub positions: Vec<[f32; 3]>,
    pub indices: Vec<u32>,
}

impl LoadedMesh {
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// Collects vertices and polygon faces, checking each as it arrives so that a loader can say
/// which element is wrong. Faces are fan-triangulated (the formats here hold convex polygons).
pub(crate) struct MeshBuilder {
    declared_vertices: usize,
    mesh: LoadedMesh,
}

impl MeshBuilder {
    /// `declared_vertices` is the count from the file's header: faces are checked against it,
    /// so faces may come before vertices.
    pub fn new(declared_vertices: usize, face_hint: usize) -> Self {
        let mut mesh = LoadedMesh::default();
        // Cap the hint: a corrupt header must not make us allocate gigabytes up front.
        mesh.positions.reserve(declared_vertices.min(1 << 24));
        mesh.indices.reserve(face_hint.min(1 << 24) * 3);
        MeshBuilder {
            declared_vertices,
            mesh,
        }
    }

    pub fn vertex(&mut self, xyz: [f64; 3]) -> Result<(), String> {
        let mut out = [0f32; 3];
        for (axis, (&value, slot)) in ["x", "y", "z"].iter().zip(xyz.iter().zip(&mut out)) {
            if value.is_nan() {
                return Err(format!("coordinate {axis} is NaN"));
            }
            if value.is_infinite() {
                return Err(format!("coordinate {axis} is {value}"));
            }
            *slot = value as f32;
            if !slot.is_finite() {
                return Err(format!("coordinate {axis} = {value:e} does not fit in f32"));
            }
        }
        self.mesh.positions.push(out);
        Ok(())
    }

    pub fn face(&mut self, face: &[i64]) -> Result<(), String> {
        if face.len() < 3 {
            return Err(format!(
                "has {} vertex indices, a face needs at least 3",
                face.len()
            ));
        }
        let count = self.declared_vertices;
        if count > u32::MAX as usize {
            return Err(format!("{count} vertices do not fit 32-bit indices"));
        }
        for &index in face {
            if index < 0 || index as u64 >= count as u64 {
                return Err(format!("references vertex {index} of {count}"));
            }
        }
        for k in 1..face.len() - 1 {
            // The casts are lossless: every index is in 0..count <= u32::MAX.
            self.mesh
                .indices
                .extend([face[0] as u32, face[k] as u32, face[k + 1] as u32]);
        }
        Ok(())
    }

    pub fn finish(self) -> Result<LoadedMesh, String> {
        let mesh = self.mesh;
        if mesh.positions.len() != self.declared_vertices {
            return Err(format!(
                "declares {} vertices but holds {}",
                self.declared_vertices,
                mesh.positions.len()
            ));
        }
        if mesh.positions.is_empty() {
            return Err("empty mesh: no vertices".into());
        }
        if mesh.indices.is_empty() {
            return Err("empty mesh: no faces".into());
        }
        Ok(mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_is_fanned_into_two_triangles() {
        let mut b = MeshBuilder::new(4, 1);
        for p in [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]] {
            b.vertex(p).unwrap();
        }
        b.face(&[0, 1, 2, 3]).unwrap();
        assert_eq!(b.finish().unwrap().indices, vec![0, 1, 2, 0, 2, 3]);
    }

    #[test]
    fn rejects_bad_vertices_and_faces() {
        let mut b = MeshBuilder::new(3, 1);
        assert_eq!(
            b.vertex([0., f64::NAN, 0.]).unwrap_err(),
            "coordinate y is NaN"
        );
        assert_eq!(
            b.vertex([f64::NEG_INFINITY, 0., 0.]).unwrap_err(),
            "coordinate x is -inf"
        );
        assert_eq!(
            b.vertex([0., 0., 1e300]).unwrap_err(),
            "coordinate z = 1e300 does not fit in f32"
        );
        assert_eq!(b.face(&[0, 1, 3]).unwrap_err(), "references vertex 3 of 3");
        assert_eq!(
            b.face(&[0, -1, 2]).unwrap_err(),
            "references vertex -1 of 3"
        );
        assert_eq!(
            b.face(&[0, 1]).unwrap_err(),
            "has 2 vertex indices, a face needs at least 3"
        );
    }
}
