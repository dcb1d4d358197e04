//! The suite's results as report rows, so `report.html` shows its tables and charts (error against
//! time, error against maps, stage breakdown) like `compare` does.

use super::suite::{MethodResult, SuiteReport};
use crate::charts::ResultRow;
use crate::methods::Method;
use crate::output;

/// One row per scene and method that has error figures (a row needs its metrics).
pub fn rows(r: &SuiteReport) -> Vec<ResultRow> {
    let adapter = serde_json::to_value(&r.adapter).unwrap_or_default();
    let mut rows = Vec::new();
    for scene in &r.scenes {
        for m in [&scene.adaptive, &scene.regular] {
            if let Some(row) = row(r, scene.seed.scene, [scene.settings[0], scene.settings[1]], scene.settings[2], m, &adapter) {
                rows.push(row);
            }
        }
    }
    rows
}

fn row(r: &SuiteReport, scene: &str, resolution: [u32; 2], map: u32, m: &MethodResult, adapter: &serde_json::Value) -> Option<ResultRow> {
    let errors = m.errors.as_ref()?;
    let method = Method::parse(&m.label, &[]).ok()?;
    Some(ResultRow {
        scene: scene.to_string(),
        method: method.name().to_string(),
        params: method.params_json(),
        adapter: adapter.clone(),
        shadow_maps: m.maps,
        total_ms: m.frame_ms.median,
        total_ms_min: m.frame_ms.min,
        total_ms_max: m.frame_ms.max,
        stages_ms: m.stages_ms.iter().map(|(k, v)| (k.clone(), v.median)).collect(),
        metrics: errors.metrics.clone(),
        label: m.label.clone(),
        syncs: m.syncs,
        total_ms_runs: m.frame_ms.samples.clone(),
        setup_ms: Some(m.setup_ms.median),
        resolution: Some(resolution),
        shadow_map_size: Some(map),
        reference: r.reference.clone().unwrap_or_default(),
        repeats: r.repeats,
        clock: "wall clock per frame (TimingMode::Frame), ms; stages_ms: the same frames' recorded stage times".into(),
        version: output::version(),
        images: Default::default(),
    })
}
