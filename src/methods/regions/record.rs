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

/// A frame's record (`run.json`'s `method_record`): the decision, the classes as shaded, and
/// with `certify` what the measurement found.
#[derive(Debug, serde::Serialize)]
pub(crate) struct RegionsRecord {
    pub(crate) region: u32,
    pub(crate) ladder: Vec<u32>,
    pub(crate) decision_maps: u32,
    pub(crate) centre_size: u32,
    pub(crate) density: f32,
    pub(crate) predicted_map: f64,
    pub(crate) classes: Vec<ClassRecord>,
    /// Σ triangles per map × maps over the rendered groups (absent where no grid rendered).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) triangle_map_pairs: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) texels_written: Option<f64>,
    /// With `certify`: the target measured and whether the frame's bound is within it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) target: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) target_met: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) certified: Option<super::certified::CertifiedRecord>,
}
