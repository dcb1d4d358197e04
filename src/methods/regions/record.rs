//! What `regions` decided for one class of a frame, shared by the method's run record and its
//! pictures (so neither module imports the other).

/// One class of a frame: the group whose maps it is shaded with, that group's grid, map size and
/// window, and the class's own tiles.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ClassRecord {
    pub class: u32,
    /// The samples per side the decision gave the class (its ladder rung).
    pub decided_n: u32,
    /// The group of classes that share one set of maps (docs/regions.md, "Groups").
    pub group: u32,
    /// The samples per side its tiles get: the group's, at or above `decided_n`.
    pub n: u32,
    pub(crate) map_size: u32,
    pub(crate) tiles: u32,
    /// The group's maps (shared by every class of the group).
    pub(crate) maps: u32,
    /// The finest texel its pixels need (tangent units from the light, per texel).
    pub(crate) texel_need: f32,
    /// The group's window side in tangent units, as the centre sees it.
    pub(crate) extent: f32,
    pub(crate) triangles_per_map_mean: f64,
}
