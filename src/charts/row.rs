//! One measured run as it arrives from the run record: what every chart and table plots.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::metrics::Metrics;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResultRow {
    pub scene: String,
    pub method: String,
    /// Method parameters, e.g. `{"p_m": 0, "scope": "local"}`.
    pub params: serde_json::Value,
    /// Adapter description (name, backend, …) the run was measured on.
    pub adapter: serde_json::Value,
    pub shadow_maps: u32,
    /// Median over repeats.
    pub total_ms: f64,
    pub total_ms_min: f64,
    pub total_ms_max: f64,
    /// Median time per stage, keyed by stage name (`reproject_count`, …).
    pub stages_ms: BTreeMap<String, f64>,
    pub metrics: Metrics,
}

impl ResultRow {
    /// `method` plus its parameters in short form: `adaptive(p_m=0, scope=local)`; just the
    /// method when there are none. Keys come in sorted order (serde_json's default map).
    pub fn label(&self) -> String {
        let p = params_short(&self.params);
        if p.is_empty() {
            self.method.clone()
        } else {
            format!("{}({p})", self.method)
        }
    }

    /// A numeric parameter, if present and finite.
    pub fn param_f64(&self, key: &str) -> Option<f64> {
        self.params.get(key)?.as_f64().filter(|v| v.is_finite())
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
