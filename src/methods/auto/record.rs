//! auto's per-frame record (run.json's `method_record`): one typed value that the method writes
//! and its readers (the lab's studies, Python's `penumbra.analysis.auto_record`) read, in the
//! JSON shape run.json files have always had, tagged `"method": "auto"`.

use super::filter::Check;
use super::Try;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The tag: which method's record this is.
pub(crate) const TAG: &str = "auto";

fn tag() -> String {
    TAG.to_string()
}

/// One frame of `auto`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AutoRecord {
    /// `auto` (records written before the tag lack it, and read as auto's).
    #[serde(default = "tag")]
    pub method: String,
    /// The grid the search settled on (or, where a filter renders, the grid it was judged by).
    pub chosen: Chosen,
    pub target: f32,
    /// The prediction (or certified bound) the frame reports is at most the target; a choice
    /// handed on and kept within the band is `kept`, not met.
    pub target_met: bool,
    /// The settling frame's tries, in order: how the choice was made.
    pub tries: Vec<Try>,
    /// The frame's predicted RMSE: the last try's, or the chosen filter's.
    pub predicted_rmse: f64,
    pub predicted_sampling: f64,
    pub predicted_map: f64,
    /// `pixels` > 0: the certified decision (docs/certify.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub certified: Option<Certified>,
    pub map_cost: MapCost,
    /// The one-map check, where it ran.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter: Option<FilterCheck>,
    /// The one-map method the frame renders instead of `chosen`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub renders: Option<String>,
    pub maps_rendered: u32,
    /// The frame ran the estimate (a settled frame renders the choice alone).
    pub estimated: bool,
    pub kept: bool,
    /// Out of reach: the line that says so (the binary prints it once per run).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub warning: Option<String>,
}

/// The centred grid chosen.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Chosen {
    pub n: u32,
    pub layout: String,
    pub map_size: u32,
    pub spec: String,
}

impl Chosen {
    pub fn centred((n, map_size): (u32, u32)) -> Chosen {
        Chosen {
            n,
            layout: "centred".into(),
            map_size,
            spec: format!("regular:n={n},layout=centred"),
        }
    }
}

/// How the search priced a map of each size.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapCost {
    pub model: String,
    /// By map side (as text, a JSON key).
    pub per_map: BTreeMap<String, f64>,
    pub pricing_ms: f64,
}

/// The one-map check (`filter`): the reference grid's try, the candidate taken, every check.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FilterCheck {
    pub reference: Option<Try>,
    pub chosen: Option<String>,
    pub checks: Vec<Check>,
    pub left_out: Vec<String>,
}

/// The certified decision: the chosen candidate's bound and what it took; the rest of its
/// detail (the design, the tests, the trace) as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Certified {
    pub(crate) bound: f64,
    pub bound_kind: crate::certify::bound::BoundKind,
    pub(crate) decision_ms: f64,
    pub tests: Vec<serde_json::Value>,
    #[serde(flatten)]
    pub(crate) detail: BTreeMap<String, serde_json::Value>,
}

impl AutoRecord {
    /// A run.json `method_record` as auto's, or None where it is another method's.
    pub fn read(record: &serde_json::Value) -> Option<AutoRecord> {
        let r: AutoRecord = serde_json::from_value(record.clone()).ok()?;
        (r.method == TAG).then_some(r)
    }

    /// The record as a frame's output carries it.
    pub fn to_value(&self) -> crate::Result<serde_json::Value> {
        serde_json::to_value(self)
            .map_err(|e| crate::Error::Limit(format!("auto: its record: {e}")))
    }

    /// The wall clock of its decision: the tries', and the certified decision's, ms.
    pub fn decision_ms(&self) -> f64 {
        self.tries.iter().map(|t| t.ms).sum::<f64>()
            + self.certified.as_ref().map_or(0.0, |c| c.decision_ms)
    }

    /// The figure the frame reports against the target: the certified bound, else the prediction.
    pub fn reported(&self) -> f64 {
        self.certified
            .as_ref()
            .map_or(self.predicted_rmse, |c| c.bound)
    }
}
