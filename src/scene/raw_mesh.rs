//! A mesh as loaded or built, before placement: what every mesh reader and subdivider passes on.

use glam::Vec3;

/// Positions + triangle indices in object space; normals are derived after the transform.
#[derive(Debug)]
pub struct RawMesh {
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    pub indices: Vec<u32>,
}
