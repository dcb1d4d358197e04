//! One record layer for `compare`, `sweep` and `bench`: one measure loop (`measure.rs`), one
//! metrics call (`judge.rs`), one row type ([`ResultRow`], with its [`Provenance`]) and one
//! `results.jsonl` schema. `penumbra report`, `merge` and `check` read any of their outputs.

pub(crate) mod csv;
pub mod judge;
pub mod measure;
pub mod output_set;
pub mod provenance;
pub mod regression;
pub(crate) mod row;
pub mod row_core;
pub mod run_files;
pub(crate) mod shaded_environment;
pub mod stats;

pub use provenance::{Provenance, SpecRef};
pub use row::{Certified, ResultRow};
pub use row_core::RowCore;

use crate::gpu::AdapterSummary;
use crate::methods::Method;
use crate::metrics::Metrics;
use crate::report::charts::svg_to_png;
use crate::{Error, Result};
use measure::Timing;
use std::collections::BTreeMap;

/// How `frame_ms` and `stages_ms` were taken (stored in every row).
pub const CLOCK: &str = "wall clock (submit to device poll wait), ms; frame_ms: frame mode (only the method's own waits); \
stages_ms: one stages-mode run (a wait after every stage)";

/// What every row of one run shares.
pub struct RunInfo<'a> {
    pub scene: &'a str,
    pub resolution: [u32; 2],
    pub shadow_map_size: u32,
    pub adapter: &'a AdapterSummary,
    /// The ground truth, e.g. `continuous 32x32`.
    pub reference: String,
    pub repeats: u32,
}

impl RunInfo<'_> {
    /// The core of `method`'s row in this run, before its figures: its label as the spec, the
    /// scene's map size, this adapter.
    fn core(&self, method: &Method) -> RowCore {
        RowCore {
            map_size: self.shadow_map_size,
            adapter: serde_json::to_value(self.adapter).unwrap_or_default(),
            ..RowCore::of(self.scene, &method.label(), method)
        }
    }
}

/// The row of one measured method.
pub fn row(
    run: &RunInfo,
    method: &Method,
    t: &Timing,
    metrics: Metrics,
    images: BTreeMap<String, String>,
    provenance: Provenance,
) -> ResultRow {
    ResultRow {
        core: RowCore {
            maps: t.shadow_maps,
            rmse: metrics.rmse,
            frame_ms: t.median_ms,
            ..run.core(method)
        },
        frame_ms_min: t.min_ms,
        frame_ms_max: t.max_ms,
        stages_ms: t.stages_ms.clone(),
        metrics,
        label: method.label(),
        syncs: t.syncs,
        frame_ms_runs: t.totals_ms.clone(),
        setup_ms: t.setup_ms,
        resolution: Some(run.resolution),
        raster: Some(t.raster.to_string()),
        reference: run.reference.clone(),
        repeats: run.repeats,
        clock: CLOCK.into(),
        images,
        provenance: Some(provenance),
        failed: None,
        certify: None,
    }
}

/// The row of a method that failed at run time: what it is and why, no figures.
pub fn failed_row(
    run: &RunInfo,
    method: &Method,
    reason: &str,
    provenance: Provenance,
) -> ResultRow {
    ResultRow {
        core: run.core(method),
        label: method.label(),
        resolution: Some(run.resolution),
        reference: run.reference.clone(),
        repeats: run.repeats,
        clock: CLOCK.into(),
        provenance: Some(provenance),
        failed: Some(reason.to_string()),
        ..Default::default()
    }
}

/// The one-line warning a study prints for a setting that failed (and goes on).
pub fn failed_line(label: &str, reason: &str) -> String {
    format!("warning: {label}: failed: {reason}")
}

/// The study's closing line on failed settings, None when none failed. Studies exit 0 when their
/// output set is complete: a failed setting is a row of it (robustness.md, "Failed settings").
pub fn failed_summary(failed: usize, total: usize) -> Option<String> {
    (failed > 0).then(|| format!("warning: {failed} of {total} settings failed; their rows say why (\"failed\" in the results)"))
}

/// `results.jsonl`: one row per line.
pub fn jsonl(rows: &[ResultRow]) -> Result<String> {
    let mut out = String::new();
    for r in rows {
        out += &serde_json::to_string(r)
            .map_err(|e| Error::io_text("results.jsonl".into(), e.to_string()))?;
        out.push('\n');
    }
    Ok(out)
}

/// The files every run writes from its rows: `results.jsonl`, `results.csv` and the charts (SVG
/// and PNG), as (path relative to the output folder, bytes).
pub fn result_files(rows: &[ResultRow]) -> Result<Vec<(String, Vec<u8>)>> {
    let mut files = vec![
        ("results.jsonl".to_string(), jsonl(rows)?.into_bytes()),
        ("results.csv".to_string(), csv::render(rows).into_bytes()),
    ];
    // For scripts: each regular grid, and the adaptive rows that dominate or nearly dominate it.
    // Charts and verdicts are of measured rows only.
    let all = rows;
    let rows: &[ResultRow] = &all
        .iter()
        .filter(|r| r.measured())
        .cloned()
        .collect::<Vec<_>>();
    let verdicts = crate::report::charts::verdicts(rows);
    if !verdicts.is_empty() {
        let json = serde_json::to_vec_pretty(&verdicts)
            .map_err(|e| crate::Error::io_text("dominance.json".into(), e.to_string()))?;
        files.push(("dominance.json".to_string(), json));
    }
    for (stem, _, svg) in crate::report::results::charts(rows)? {
        files.push((format!("charts/{stem}.png"), svg_to_png(&svg, 1.0)?));
        files.push((format!("charts/{stem}.svg"), svg.into_bytes()));
    }
    Ok(files)
}
