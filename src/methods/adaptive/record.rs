//! adaptive's per-frame record (run.json's `method_record`): one typed value, in the JSON shape
//! run.json files have always had. `levels::record` fills the frame's figures; the host- and
//! GPU-steered loops add what only they know, and `growth` the item list's growth.

use crate::methods::hybrid_maps::HybridRecord;

/// One frame of `adaptive`.
#[derive(serde::Serialize)]
pub(crate) struct AdaptiveRecord {
    pub(crate) levels: Vec<LevelRecord>,
    /// Read-backs the frame needed (with growth: those of the frames run again as well).
    pub(crate) syncs: u32,
    /// Lattice samples rendered, in order.
    pub(crate) shadow_maps_used: Vec<u32>,
    pub(crate) triangles_per_map: Vec<u64>,
    pub(crate) triangles_per_map_mean: f64,
    pub(crate) culled_maps: usize,
    /// The weight rule, in words.
    pub(crate) weights: String,
    /// scope = local with pictures: the samples each geometry pixel consulted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) samples_per_pixel_mean: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) samples_per_pixel_max: Option<u32>,
    /// maps = hybrid: the hybrid store's figures.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) hybrid: Option<HybridRecord>,
    /// The GPU-steered loop: how it steered, and what each level rasterized.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) steer: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) steer_raster: Option<&'static str>,
}

impl AdaptiveRecord {
    /// The record as a frame's output carries it.
    pub(crate) fn to_value(&self) -> crate::Result<serde_json::Value> {
        crate::methods::record_value("adaptive", self)
    }
}

/// scope = local: what the item list grew to (run.json `items`), added by `growth` to the frame
/// that fitted.
#[derive(serde::Serialize)]
pub(crate) struct ItemsRecord {
    pub(crate) capacity: u32,
    pub(crate) frames_run_again: usize,
    pub(crate) grown_to: Vec<u32>,
}

/// Per-level summary for run.json.
#[derive(serde::Serialize)]
pub(crate) struct LevelRecord {
    pub(crate) level: u32,
    pub(crate) active_quads: usize,
    /// [i, j, size, parent index in the previous level] of each evaluated quad, in counter order.
    pub(crate) quads: Vec<[u32; 4]>,
    pub(crate) low_quality_per_quad: Vec<u32>,
    pub(crate) split_quads: usize,
    pub(crate) new_samples: usize,
    pub(crate) pixels_evaluated: u64,
    /// scope = local: shadow-map lookups (pixel, sample pairs tested for the first time).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) lookups: Option<u64>,
}
