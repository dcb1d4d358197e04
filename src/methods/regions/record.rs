//! `regions`' frame record (run.json's `method_record`): what it decided for each class, shared
//! by the record and the pictures (so neither module imports the other), and with `certify` what
//! the measurement found. The types sit here, below the modules that fill them.

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
    pub(crate) certified: Option<CertifiedRecord>,
}

/// One class's measurement, as the record keeps it.
#[derive(Clone, Debug, serde::Serialize)]
pub(crate) struct ClassMeasure {
    pub(crate) class: u32,
    /// `pcss`, or `regular:n=N,layout=centred @ SIZE`.
    pub(crate) setting: String,
    /// Step-ups after the plan (0: the plan, or the filter, was certified).
    pub(crate) steps: u32,
    /// The bound on the class's RMSE at confidence 1 − δ/C (each setting's at δ/(C·S)), and the
    /// sampled RMSE.
    pub(crate) bound: f64,
    pub(crate) sampled_rmse: f64,
    pub(crate) certified: bool,
    /// The bound of each setting tried, in order.
    pub(crate) tried: Vec<(String, f64)>,
    /// Geometry pixels in the class (N_c) and their share of the frame's.
    pub(crate) pixels: usize,
    pub(crate) share: f64,
}

/// What the certified decision adds to the frame's record (`method_record.certified`).
#[derive(Debug, serde::Serialize)]
pub(crate) struct CertifiedRecord {
    pub(crate) decision_ms: f64,
    /// The frame's bound on its RMSE, at confidence 1 − delta.
    pub(crate) bound: f64,
    pub(crate) delta: f32,
    /// Each setting's bound is at this confidence, δ/(C·S): C classes, S settings a class could
    /// end on (`reachable_settings`), so the chosen ones hold at 1 − δ however they were chosen.
    pub(crate) delta_per_setting: f64,
    pub(crate) reachable_settings: usize,
    pub(crate) pixels_per_class: u32,
    pub(crate) traced_pixels: usize,
    pub(crate) trace_ms: f64,
    pub(crate) rays: u64,
    pub(crate) classes: Vec<ClassMeasure>,
    /// The frame started from the settings the previous frame ended on (`hold`).
    pub(crate) held: bool,
    pub(crate) fallback: FallbackRecord,
    pub(crate) clock: &'static str,
}

/// Whether a fresh frame took the frame-wide setting, and why (the predicted costs); a held frame
/// decides none and carries neither cost.
#[derive(Debug, serde::Serialize)]
pub(crate) struct FallbackRecord {
    pub(crate) taken: bool,
    pub(crate) setting: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) plan_cost: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) frame_wide_cost: Option<f64>,
    pub(crate) ratio: Option<f32>,
}

impl FallbackRecord {
    pub(crate) fn held() -> FallbackRecord {
        FallbackRecord {
            taken: false,
            setting: None,
            plan_cost: None,
            frame_wide_cost: None,
            ratio: None,
        }
    }
}
