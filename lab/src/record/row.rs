//! One measured run as it arrives from the run record: what every chart and table plots.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::metrics::Metrics;
use crate::record::RowCore;

/// A number as a message shows it: as written for ordinary sizes, in exponent form far from 1
/// (`1e308`, not 309 digits).
pub fn shown(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e15).contains(&v.abs()) {
        v.to_string()
    } else {
        format!("{v:e}")
    }
}

/// The longest time a row read back may hold, in ms: about 32 years.
pub const MAX_MS: f64 = 1e12;

/// One row of `results.jsonl`. The keys up to `metrics` are what every chart needs; the rest
/// (all optional when read back) say how the row was measured and where its pictures are.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ResultRow {
    /// Scene, spec, method, params, maps, map size, RMSE (`metrics.rmse`), frame time (the median
    /// over repeats), adapter, version and target: the keys every study's row shares.
    #[serde(flatten)]
    pub core: RowCore,
    #[serde(alias = "total_ms_min")]
    pub frame_ms_min: f64,
    #[serde(alias = "total_ms_max")]
    pub frame_ms_max: f64,
    /// Median time per stage, keyed by stage name (`reproject_count`, …).
    pub stages_ms: BTreeMap<String, f64>,
    pub metrics: Metrics,
    /// The method's own short label (`adaptive:p_m=0,scope=local`); empty: derived from params.
    #[serde(default)]
    pub label: String,
    /// CPU↔GPU synchronisations the method needs per frame (read-backs), timing waits excluded.
    #[serde(default)]
    pub syncs: u32,
    /// Every timed frame, in run order (`frame_ms` is their median).
    #[serde(default, alias = "total_ms_runs")]
    pub frame_ms_runs: Vec<f64>,
    /// Per-frame setup outside `frame_ms` (pipelines, upload), from the stages-mode run.
    #[serde(default)]
    pub setup_ms: Option<f64>,
    /// `[width, height]` of the image the metrics are taken over.
    #[serde(default)]
    pub resolution: Option<[u32; 2]>,
    /// `hardware` or `compute`: who rasterized the maps (the `raster` setting, `auto` resolved).
    #[serde(default)]
    pub raster: Option<String>,
    /// The ground truth the metrics compare with, e.g. `continuous 32x32`.
    #[serde(default)]
    pub reference: String,
    #[serde(default)]
    pub repeats: u32,
    /// Which clock the times come from and how they were taken.
    #[serde(default)]
    pub clock: String,
    /// Picture files (`shaded`, `visibility`, `abs_error`, `signed_error`, `reference`), relative
    /// to the results file.
    #[serde(default)]
    pub images: BTreeMap<String, String>,
    /// Scene and mesh digests, overrides, and the sweep spec and shard (see `record::provenance`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub provenance: Option<crate::record::Provenance>,
    /// A setting that failed at run time (an overflow, out of memory, any per-setting error): the
    /// reason, one line. Its figures are zero and mean nothing; tables, charts and fronts skip it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
    /// `--certify K`: the certified bound on this row's RMSE (docs/certify.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub certify: Option<Certified>,
}

/// What a row keeps of its certificate: enough for "RMSE ≤ U at 95% (K px, X ms)".
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Certified {
    pub pixels: usize,
    pub delta: f64,
    pub bound: f64,
    pub bound_kind: String,
    pub sampled_rmse: f64,
    /// Wall clock of the certificate (second opinion, draw, trace, bounds), ms.
    pub pixels_ms: f64,
}

impl Certified {
    pub fn of(r: &crate::frame::certify::CertifyRecord) -> Certified {
        let c = &r.certificate;
        Certified {
            pixels: c.pixels,
            delta: c.delta,
            bound: c.bound,
            bound_kind: c.bound_kind.name().to_string(),
            sampled_rmse: c.sampled_rmse,
            pixels_ms: r.pixels_ms,
        }
    }

    /// `RMSE ≤ 0.0234 at 95% (2048 px, 85 ms)`.
    pub fn line(&self) -> String {
        format!(
            "RMSE ≤ {:.4} at {}% ({} px, {:.0} ms)",
            self.bound,
            confidence(self.delta),
            self.pixels,
            self.pixels_ms
        )
    }
}

/// 1 − δ as a percentage, without trailing zeros: 95, 99.9.
pub fn confidence(delta: f64) -> String {
    let p = format!("{:.3}", 100.0 * (1.0 - delta));
    p.trim_end_matches('0').trim_end_matches('.').to_string()
}

impl ResultRow {
    /// One line of `results.jsonl`. A row written before the one schema carries its RMSE only in
    /// `metrics.rmse`: the core's `rmse` is filled from it.
    pub fn from_json(line: &str) -> serde_json::Result<ResultRow> {
        let mut row: ResultRow = serde_json::from_str(line)?;
        if row.core.rmse == 0.0 {
            row.core.rmse = row.metrics.rmse;
        }
        Ok(row)
    }

    /// Whether the row was measured (not a failed setting).
    pub fn measured(&self) -> bool {
        self.failed.is_none()
    }

    /// The stored label, else `method` plus its parameters in short form:
    /// `adaptive(p_m=0, scope=local)`; just the method when there are none. Keys come in sorted
    /// order (serde_json's default map).
    pub fn label(&self) -> String {
        if !self.label.is_empty() {
            return self.label.clone();
        }
        let p = params_short(&self.core.params);
        if p.is_empty() {
            self.core.method.clone()
        } else {
            format!("{}({p})", self.core.method)
        }
    }

    /// What is wrong with a row read back, as `key = value: why` (None: nothing). A measured row's
    /// errors of V lie in [0, 1] and its times are finite and non-negative; a value outside is a
    /// damaged or hand-made file, which charts would otherwise stretch their axes to (an RMSE of
    /// 1e308 made `report` walk two billion log decades). A failed row's figures mean nothing and
    /// are not read.
    pub fn check(&self) -> Option<String> {
        if !self.measured() {
            return None;
        }
        let m = &self.metrics;
        let shares = [
            ("metrics.rmse", Some(m.rmse)),
            ("metrics.mae", Some(m.mae)),
            ("metrics.max_abs", Some(m.max_abs)),
            ("metrics.penumbra_rmse", m.penumbra_rmse),
            ("metrics.bad_pixel_share", Some(m.bad_pixel_share)),
            ("metrics.mismatch_share", Some(m.mismatch_share)),
            ("metrics.flip_mean", Some(m.flip_mean)),
            ("metrics.flip_p95", Some(m.flip_p95)),
            ("metrics.flip_p99", Some(m.flip_p99)),
        ];
        for (key, v) in shares {
            if let Some(v) = v.filter(|v| !(0.0..=1.0).contains(v)) {
                return Some(format!(
                    "{key} = {}: an error or share of V lies in [0, 1]",
                    shown(v)
                ));
            }
        }
        if self.core.rmse.to_bits() != m.rmse.to_bits() {
            return Some(format!(
                "rmse = {}: differs from metrics.rmse = {} (one figure, written twice)",
                shown(self.core.rmse),
                shown(m.rmse)
            ));
        }
        if let Some(v) = m.psnr.filter(|v| !v.is_finite()) {
            return Some(format!(
                "metrics.psnr = {v}: must be a finite number (null where the error is 0)"
            ));
        }
        let times = [
            ("frame_ms", self.core.frame_ms),
            ("frame_ms_min", self.frame_ms_min),
            ("frame_ms_max", self.frame_ms_max),
            ("setup_ms", self.setup_ms.unwrap_or(0.0)),
        ];
        let stages = self
            .stages_ms
            .iter()
            .map(|(k, v)| (format!("stages_ms.{k}"), *v));
        let runs = self
            .frame_ms_runs
            .iter()
            .enumerate()
            .map(|(i, v)| (format!("frame_ms_runs[{i}]"), *v));
        for (key, v) in times
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .chain(stages)
            .chain(runs)
        {
            if !(0.0..=MAX_MS).contains(&v) {
                return Some(format!("{key} = {}: a time in ms must be finite, at least 0 and at most {MAX_MS:e} (a year is 3.2e10)", shown(v)));
            }
        }
        None
    }

    /// A numeric parameter, if present and finite.
    pub fn param_f64(&self, key: &str) -> Option<f64> {
        self.core
            .params
            .get(key)?
            .as_f64()
            .filter(|v| v.is_finite())
    }
}

/// `k=v, k=v` for an object (strings unquoted), the compact JSON otherwise, "" for null/{}.
pub fn params_short(params: &serde_json::Value) -> String {
    match params {
        serde_json::Value::Null => String::new(),
        serde_json::Value::Object(map) => map
            .iter()
            .map(|(k, v)| format!("{k}={}", value_short(v)))
            .collect::<Vec<_>>()
            .join(", "),
        other => value_short(other),
    }
}

fn value_short(v: &serde_json::Value) -> String {
    match v {
        serde_json::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn a_certified_row_reads_as_one_line() {
        let c = Certified {
            pixels: 2048,
            delta: 0.05,
            bound: 0.02345,
            bound_kind: "calibrated".into(),
            sampled_rmse: 0.02,
            pixels_ms: 84.6,
        };
        assert_eq!(c.line(), "RMSE ≤ 0.0234 at 95% (2048 px, 85 ms)");
        assert_eq!(confidence(0.001), "99.9");
    }

    #[test]
    fn labels() {
        assert_eq!(
            params_short(&json!({"scope": "local", "p_m": 0})),
            "p_m=0, scope=local"
        );
        assert_eq!(params_short(&json!(null)), "");
        assert_eq!(params_short(&json!({})), "");
        assert_eq!(
            params_short(&json!({"n": 17, "w": [1, 2]})),
            "n=17, w=[1,2]"
        );
    }
}
