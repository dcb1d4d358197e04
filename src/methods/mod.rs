//! Shadow methods. Each one produces the same thing over the same G-buffer: a visibility image,
//! a count of shadow maps and a record, so every method lands on the same charts.

pub mod adaptive;
pub mod fixed;
pub mod params;

pub use fixed::Layout;
pub use params::{AdaptiveParams, Criterion, Preset, Scope, Weights};

use crate::{Error, Result};
use std::collections::BTreeMap;

#[derive(Clone, Debug, PartialEq)]
pub enum Method {
    /// One shadow map from the light's centre.
    Hard,
    /// N×N grid of samples over the light, in one of three layouts (`fixed::regular_points`).
    Regular { n: u32, layout: Layout },
    /// Adaptive light-source sampling (seed 000), with this project's extensions.
    Adaptive(AdaptiveParams),
}

pub const METHOD_NAMES: &[&str] = &["hard", "regular", "adaptive"];
pub const METHOD_KEYS: &[&str] = &["n", "layout", "preset", "p_m", "p_share", "growth", "tol", "max_level", "weights", "scope", "scissor"];

impl Method {
    /// `name` or `name:key=value,key=value`, plus `--set` pairs whose keys are method parameters.
    pub fn parse(spec: &str, extra: &[(String, String)]) -> Result<Method> {
        let (name, inline) = match spec.split_once(':') {
            Some((n, rest)) => (n, rest),
            None => (spec, ""),
        };
        let mut params = BTreeMap::new();
        for pair in inline.split(',').filter(|s| !s.is_empty()) {
            let (k, v) = pair
                .split_once('=')
                .ok_or_else(|| Error::Param(format!("method `{spec}`: `{pair}` is not key=value")))?;
            params.insert(k.trim().to_string(), v.trim().to_string());
        }
        for (k, v) in extra {
            params.insert(k.clone(), v.clone());
        }
        let allowed: &[&str] = match name {
            "hard" => &[],
            "regular" => &["n", "layout"],
            "adaptive" => &["preset", "p_m", "p_share", "growth", "tol", "max_level", "weights", "scope", "scissor"],
            _ => {
                return Err(Error::Param(format!("unknown method `{name}` (known: {})", METHOD_NAMES.join(", "))));
            }
        };
        if let Some(k) = params.keys().find(|k| !allowed.contains(&k.as_str())) {
            return Err(Error::Param(format!(
                "method `{name}` has no parameter `{k}` (its parameters: {})",
                if allowed.is_empty() { "none".to_string() } else { allowed.join(", ") }
            )));
        }
        Ok(match name {
            "hard" => Method::Hard,
            "regular" => {
                let n = params::get_u32(&params, "n", 17)?;
                if n == 0 || n > 128 {
                    return Err(Error::Param(format!("regular: n must be in 1..=128, got {n}")));
                }
                let layout = match params.get("layout").map(String::as_str) {
                    None | Some("lattice") => Layout::Lattice,
                    Some("centred") | Some("centered") => Layout::Centred,
                    Some("jittered") => Layout::Jittered,
                    Some(v) => return Err(Error::Param(format!("regular: layout = `{v}`: use `lattice`, `centred` or `jittered`"))),
                };
                Method::Regular { n, layout }
            }
            _ => Method::Adaptive(AdaptiveParams::from_map(&params)?),
        })
    }

    /// Today's regular grid: the N×N lattice, corners included.
    pub fn regular(n: u32) -> Method {
        Method::Regular { n, layout: Layout::Lattice }
    }

    pub fn name(&self) -> &'static str {
        match self {
            Method::Hard => "hard",
            Method::Regular { .. } => "regular",
            Method::Adaptive(_) => "adaptive",
        }
    }

    /// Parameters as the run record states them (every parameter, defaults included).
    pub fn params_json(&self) -> serde_json::Value {
        match self {
            Method::Hard => serde_json::json!({}),
            Method::Regular { n, layout } => serde_json::json!({ "n": n, "layout": layout }),
            Method::Adaptive(p) => serde_json::to_value(p).unwrap_or_default(),
        }
    }

    /// Short label for tables and charts: `adaptive:p_m=0,scope=local`.
    pub fn label(&self) -> String {
        match self {
            Method::Hard => "hard".into(),
            Method::Regular { n, layout: Layout::Lattice } => format!("regular:n={n}"),
            Method::Regular { n, layout: Layout::Centred } => format!("regular:n={n},layout=centred"),
            Method::Regular { n, layout: Layout::Jittered } => format!("regular:n={n},layout=jittered"),
            Method::Adaptive(p) => p.label(),
        }
    }
}
