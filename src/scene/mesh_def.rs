//! A `[[mesh]]` table of the scene format (docs/scene-format.md): what to load or build, and where
//! to place it.

use super::subdivide::Scheme;
use serde::Deserialize;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(crate) struct MeshDef {
    pub(crate) builtin: Option<String>,
    pub(crate) file: Option<String>,
    #[serde(default)]
    pub(crate) translate: [f32; 3],
    #[serde(default)]
    pub(crate) rotate_deg: [f32; 3],
    #[serde(default)]
    pub(crate) scale: Scale,
    #[serde(default = "default_albedo")]
    pub(crate) albedo: [f32; 3],
    #[serde(default = "default_segments")]
    pub(crate) segments: u32,
    /// Rounds of subdivision (×4 triangles each): reaches a seed's triangle count.
    #[serde(default)]
    pub(crate) subdivide: u32,
    /// `midpoint` (default: the surface unchanged) or `loop` (smooth).
    #[serde(default)]
    pub(crate) subdivision: Scheme,
    /// Placements `[x, y, z, rot_y_deg, scale]`, each applied after the mesh's own transform.
    pub(crate) instances: Option<Vec<[f32; 5]>>,
    /// A grid of placements in the xz plane (see `GridDef`); exclusive with `instances`.
    pub(crate) grid: Option<GridDef>,
}

/// `grid = { count = [nx, nz], spacing = [dx, dz], rotate_step_deg = 0 }`: centred on the origin;
/// instance k (x fastest) is turned k · rotate_step_deg about y.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(crate) struct GridDef {
    pub(crate) count: [u32; 2],
    pub(crate) spacing: [f32; 2],
    #[serde(default)]
    pub(crate) rotate_step_deg: f32,
}

#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(untagged)]
pub(crate) enum Scale {
    Uniform(f32),
    Axes([f32; 3]),
}

impl Default for Scale {
    fn default() -> Self {
        Scale::Uniform(1.0)
    }
}

fn default_albedo() -> [f32; 3] {
    [0.8, 0.8, 0.8]
}
fn default_segments() -> u32 {
    32
}
