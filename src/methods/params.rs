//! Adaptive method parameters (`--set p_m=0`, `adaptive:scope=local`).

use crate::{Error, Result};
use serde::Serialize;
use std::collections::BTreeMap;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Weights {
    /// The seed's rule: w_i = 1 / (2^level_i + 1)², normalised.
    Level,
    /// Each leaf quad weighted by its area, the mean of its corners.
    Area,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Scope {
    /// The seed: final shading reads every map for every pixel.
    Global,
    /// Region-local refinement: children evaluated only over the parent's penumbra pixels.
    Local,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AdaptiveParams {
    /// Split threshold in pixels; `inf` never splits, -1 always splits. JSON has no infinity, so
    /// run records hold the string "inf" there.
    #[serde(serialize_with = "number_or_inf")]
    pub p_m: f64,
    pub max_level: u32,
    pub weights: Weights,
    pub scope: Scope,
    pub scissor: bool,
}

fn number_or_inf<S: serde::Serializer>(v: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    match *v {
        f64::INFINITY => s.serialize_str("inf"),
        f64::NEG_INFINITY => s.serialize_str("-inf"),
        x => s.serialize_f64(x),
    }
}

impl Default for AdaptiveParams {
    fn default() -> Self {
        Self { p_m: 0.0, max_level: 4, weights: Weights::Level, scope: Scope::Global, scissor: false }
    }
}

pub fn get_u32(params: &BTreeMap<String, String>, key: &str, default: u32) -> Result<u32> {
    match params.get(key) {
        None => Ok(default),
        Some(v) => v.parse().map_err(|_| Error::Param(format!("parameter {key} = `{v}` is not a non-negative integer"))),
    }
}

impl AdaptiveParams {
    pub fn from_map(params: &BTreeMap<String, String>) -> Result<Self> {
        let mut p = Self::default();
        if let Some(v) = params.get("p_m") {
            p.p_m = match v.as_str() {
                "inf" | "+inf" | "infinity" => f64::INFINITY,
                _ => v.parse().map_err(|_| Error::Param(format!("p_m = `{v}` is not a number (or `inf`)")))?,
            };
            if p.p_m.is_nan() {
                return Err(Error::Param("p_m must not be NaN".into()));
            }
        }
        p.max_level = get_u32(params, "max_level", 4)?;
        if p.max_level > 4 {
            return Err(Error::Param(format!(
                "max_level = {} exceeds the lattice of method.md §3 (L_max = 4, 17x17 points)",
                p.max_level
            )));
        }
        if let Some(v) = params.get("weights") {
            p.weights = match v.as_str() {
                "level" => Weights::Level,
                "area" => Weights::Area,
                _ => return Err(Error::Param(format!("weights = `{v}`: use `level` or `area`"))),
            };
        }
        if let Some(v) = params.get("scope") {
            p.scope = match v.as_str() {
                "global" => Scope::Global,
                "local" => Scope::Local,
                _ => return Err(Error::Param(format!("scope = `{v}`: use `global` or `local`"))),
            };
        }
        if let Some(v) = params.get("scissor") {
            p.scissor = match v.as_str() {
                "on" | "true" => true,
                "off" | "false" => false,
                _ => return Err(Error::Param(format!("scissor = `{v}`: use `on` or `off`"))),
            };
        }
        if p.scissor && p.scope != Scope::Local {
            return Err(Error::Param("scissor = on needs scope = local (only then are a map's pixels known)".into()));
        }
        Ok(p)
    }

    /// Split threshold as the kernel compares it: split when count > threshold.
    /// -1 (or any negative) ⇒ always split; +inf ⇒ never.
    pub fn threshold(&self) -> (u32, bool, bool) {
        let always = self.p_m < 0.0;
        let never = self.p_m == f64::INFINITY || self.p_m >= u32::MAX as f64;
        (if always || never { 0 } else { self.p_m.floor() as u32 }, always, never)
    }

    pub fn label(&self) -> String {
        let mut s = format!("adaptive:p_m={}", self.p_m);
        if self.max_level != 4 {
            s += &format!(",max_level={}", self.max_level);
        }
        if self.weights != Weights::Level {
            s += ",weights=area";
        }
        if self.scope == Scope::Local {
            s += ",scope=local";
        }
        if self.scissor {
            s += ",scissor=on";
        }
        s
    }
}
