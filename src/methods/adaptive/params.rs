//! Adaptive method parameters (`adaptive:p_m=0,scope=local`, or `penumbra render --param p_m=0`).

use super::super::{get_u32, Layout};
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
    /// Each leaf quad integrated as a Coons patch through every rendered sample on its edges, so the
    /// samples its split neighbours added count for it too (docs/method.md §3).
    Coons,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Scope {
    /// The seed: final shading reads every map for every pixel.
    Global,
    /// Region-local refinement: children evaluated only over the parent's penumbra pixels.
    Local,
}

/// When a quad is split (docs/method.md §6). Every rule compares the quad's low-quality pixel count
/// with a threshold; they differ in how the threshold is set.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "criterion", rename_all = "lowercase")]
pub enum Criterion {
    /// The seed: split when count > p_m pixels (x growth^level). p_m < 0 always splits, inf never.
    /// JSON has no infinity, so run records hold the string "inf" there.
    Pixels {
        #[serde(serialize_with = "number_or_inf")]
        p_m: f64,
        growth: f64,
    },
    /// Resolution-independent: split when count > p_share x geometry pixels (x growth^level).
    Share { p_share: f64, growth: f64 },
    /// Error budget: split when the RMSE the quad's flagged pixels are estimated to leave,
    /// KAPPA x area share x sqrt(count / geometry pixels), exceeds tol.
    Tol { tol: f64 },
}

/// RMS error of a quad's 4-corner estimate, in units of the quad's share of the light, when a
/// straight shadow edge crosses it and its corners disagree (measured: 0.199 over 3,000 random
/// edges; docs/method.md §6).
pub(crate) const KAPPA: f64 = 0.2;

pub(crate) use crate::stages::subdivide::SplitRule;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Preset {
    /// The seed's method exactly: p_m = 0, level weights, global scope.
    Seed,
    /// The project's recommendation, chosen from measurements (results/bench-fair-baselines/).
    Balanced,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AdaptiveParams {
    pub preset: Option<Preset>,
    #[serde(flatten)]
    pub criterion: Criterion,
    pub max_level: u32,
    pub weights: Weights,
    pub scope: Scope,
    pub scissor: bool,
    /// Per-map triangle culling to the tiles the map's pixels test (scope = local); off by default
    /// (docs/gpu-frame.md: on lavapipe it costs more than it saves).
    pub cull: Option<bool>,
    /// `steer = cpu` (the default): read each level back and record the next from the CPU (the
    /// waiting loop); `steer = gpu`: the GPU steers the levels where it can, with no read-back
    /// (docs/gpu-frame.md). The waiting loop is the default because it measured faster on an
    /// H100 and no slower on lavapipe (docs/bench.md).
    pub steer_cpu: bool,
    /// Where the quadtree's lattice sits on the light (docs/method.md §7.1): `lattice` spans the
    /// light corner to corner (the seed); `centred` is inset by half a finest cell, so that the full
    /// lattice at max_level is the centred (midpoint-rule) grid.
    pub layout: Layout,
    /// scope = local: the (pixel, quad) item list's starting capacity (default 32 per pixel, at
    /// most what one storage binding holds); tests lower it to make a frame overflow.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub items: Option<u32>,
    /// scope = local: a frame that overflows the item list runs again on a list grown from the
    /// count (`items_grow = off`: it fails with the overflow instead; never clipped).
    #[serde(skip_serializing_if = "is_on")]
    pub items_grow: bool,
    /// Hysteresis (docs/reuse.md): a quad the previous frame of the same renderer or sequence did
    /// not split splits only with `hold` low-quality pixels past its threshold; one it split
    /// merges only at or below the threshold. 0: no hysteresis (every frame decides afresh).
    #[serde(skip_serializing_if = "is_zero")]
    pub hold: u32,
}

fn is_zero(v: &u32) -> bool {
    *v == 0
}

/// Serialize `items_grow` only when it is off (the default adds nothing to a record).
fn is_on(b: &bool) -> bool {
    *b
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
        Self {
            preset: None,
            criterion: Criterion::Pixels {
                p_m: 0.0,
                growth: 1.0,
            },
            max_level: 4,
            weights: Weights::Level,
            scope: Scope::Global,
            scissor: false,
            layout: Layout::Lattice,
            cull: None,
            steer_cpu: true,
            items: None,
            items_grow: true,
            hold: 0,
        }
    }
}

fn get_f64(params: &BTreeMap<String, String>, key: &str) -> Result<Option<f64>> {
    let Some(v) = params.get(key) else {
        return Ok(None);
    };
    let x: f64 = match v.as_str() {
        "inf" | "+inf" | "infinity" => f64::INFINITY,
        _ => v
            .parse()
            .map_err(|_| Error::Param(format!("parameter {key} = `{v}` is not a number")))?,
    };
    if x.is_nan() {
        return Err(Error::Param(format!(
            "parameter {key} = `{v}` must not be NaN"
        )));
    }
    Ok(Some(x))
}

impl AdaptiveParams {
    /// The recommended setting (results/bench-fair-baselines/, "Choosing `balanced`"): the seed's zero threshold, no
    /// split below level 3 (at the seed's 512² maps the shadow maps' own error dominates past the
    /// 9x9 lattice), Coons weights, global scope.
    pub(crate) fn balanced() -> Self {
        Self {
            preset: Some(Preset::Balanced),
            max_level: 3,
            weights: Weights::Coons,
            ..Self::default()
        }
    }

    pub(crate) fn from_map(params: &BTreeMap<String, String>) -> Result<Self> {
        let mut p = match params.get("preset").map(String::as_str) {
            None => Self::default(),
            Some("seed") => Self {
                preset: Some(Preset::Seed),
                ..Self::default()
            },
            Some("balanced") => Self::balanced(),
            Some(v) => {
                return Err(Error::Param(format!(
                    "preset = `{v}`: use `seed` or `balanced`"
                )))
            }
        };
        let given: Vec<&str> = ["p_m", "p_share", "tol"]
            .into_iter()
            .filter(|k| params.contains_key(*k))
            .collect();
        if given.len() > 1 {
            return Err(Error::Param(format!(
                "adaptive: give one split criterion, not {}",
                given.join(" and ")
            )));
        }
        let growth = get_f64(params, "growth")?;
        if let Some(g) = growth {
            if !(1.0..=1e6).contains(&g) {
                return Err(Error::Param(format!(
                    "growth = {g}: the level factor must be in [1, 1e6]"
                )));
            }
        }
        if let Some(p_m) = get_f64(params, "p_m")? {
            p.criterion = Criterion::Pixels {
                p_m,
                growth: growth.unwrap_or(1.0),
            };
        } else if let Some(p_share) = get_f64(params, "p_share")? {
            if !(0.0..=1.0).contains(&p_share) {
                return Err(Error::Param(format!(
                    "p_share = {p_share}: a share of the geometry pixels, in [0, 1]"
                )));
            }
            p.criterion = Criterion::Share {
                p_share,
                growth: growth.unwrap_or(1.0),
            };
        } else if let Some(tol) = get_f64(params, "tol")? {
            if !(tol > 0.0 && tol.is_finite()) {
                return Err(Error::Param(format!(
                    "tol = {tol}: the error budget must be a positive finite RMSE"
                )));
            }
            p.criterion = Criterion::Tol { tol };
        } else if let Some(g) = growth {
            match &mut p.criterion {
                Criterion::Pixels { growth, .. } | Criterion::Share { growth, .. } => *growth = g,
                Criterion::Tol { .. } => {
                    return Err(Error::Param(
                        "growth applies to p_m or p_share; tol sets its own level factor (16)"
                            .into(),
                    ))
                }
            }
        }
        if growth.is_some() && matches!(p.criterion, Criterion::Tol { .. }) {
            return Err(Error::Param(
                "growth applies to p_m or p_share; tol sets its own level factor (16)".into(),
            ));
        }
        p.max_level = get_u32(params, "max_level", p.max_level)?;
        if p.max_level > 4 {
            return Err(Error::Param(format!(
                "max_level = {} exceeds the lattice of docs/method.md §3 (L_max = 4, 17x17 points)",
                p.max_level
            )));
        }
        if let Some(v) = params.get("weights") {
            p.weights = match v.as_str() {
                "level" => Weights::Level,
                "area" => Weights::Area,
                "coons" => Weights::Coons,
                _ => {
                    return Err(Error::Param(format!(
                        "weights = `{v}`: use `level`, `area` or `coons`"
                    )))
                }
            };
        }
        if let Some(v) = params.get("scope") {
            p.scope = match v.as_str() {
                "global" => Scope::Global,
                "local" => Scope::Local,
                _ => {
                    return Err(Error::Param(format!(
                        "scope = `{v}`: use `global` or `local`"
                    )))
                }
            };
        }
        // Local scope sums each pixel's own leaf quads by area (docs/method.md §4.2); it has no use
        // for sample weights, so a preset's weights become area there and others are refused.
        if p.scope == Scope::Local {
            match params.get("weights").map(String::as_str) {
                None | Some("area") => p.weights = Weights::Area,
                Some(v) => {
                    return Err(Error::Param(format!(
                        "weights = `{v}` applies to scope = global; scope = local integrates each pixel's own quads by area (use weights=area or leave it out)"
                    )))
                }
            }
        }
        if let Some(v) = params.get("scissor") {
            p.scissor = match v.as_str() {
                "on" | "true" => true,
                "off" | "false" => false,
                _ => return Err(Error::Param(format!("scissor = `{v}`: use `on` or `off`"))),
            };
        }
        if let Some(v) = params.get("cull") {
            p.cull = Some(match v.as_str() {
                "on" | "true" => true,
                "off" | "false" => false,
                _ => return Err(Error::Param(format!("cull = `{v}`: use `on` or `off`"))),
            });
        }
        if let Some(v) = params.get("steer") {
            p.steer_cpu = match v.as_str() {
                "gpu" => false,
                "cpu" => true,
                _ => {
                    return Err(Error::Param(format!(
                        "adaptive: steer = `{v}`: use `gpu` or `cpu`"
                    )))
                }
            };
        }
        if let Some(v) = params.get("items") {
            match v.parse::<u32>() {
                Ok(n) if n >= 1 => p.items = Some(n),
                _ => {
                    return Err(Error::Param(format!(
                        "adaptive: items = `{v}`: use a whole number of items, at least 1"
                    )))
                }
            }
            if p.scope != Scope::Local {
                return Err(Error::Param(
                    "adaptive: items needs scope = local (only it keeps an item list)".into(),
                ));
            }
        }
        if let Some(v) = params.get("items_grow") {
            p.items_grow = match v.as_str() {
                "on" | "true" => true,
                "off" | "false" => false,
                _ => {
                    return Err(Error::Param(format!(
                        "adaptive: items_grow = `{v}`: use `on` or `off`"
                    )))
                }
            };
            if p.scope != Scope::Local {
                return Err(Error::Param(
                    "adaptive: items_grow needs scope = local (only it keeps an item list)".into(),
                ));
            }
        }
        p.hold = super::HOLD.get(params, "adaptive")?;
        if let Some(v) = params.get("layout") {
            p.layout = match v.as_str() {
                "lattice" => Layout::Lattice,
                "centred" | "centered" => Layout::Centred,
                "jittered" => return Err(Error::Param("adaptive: layout = `jittered`: the quadtree needs nested samples; use `lattice` or `centred`".into())),
                _ => return Err(Error::Param(format!("adaptive: layout = `{v}`: use `lattice` or `centred`"))),
            };
        }
        if p.layout == Layout::Centred && p.scope == Scope::Local {
            return Err(Error::Param("adaptive: layout = centred needs scope = global (local scope counts uniform quad shares; the border strips are not uniform)".into()));
        }
        if p.layout == Layout::Centred && p.weights == Weights::Level {
            return Err(Error::Param("adaptive: layout = centred needs weights = area or coons (the level rule has no border strips)".into()));
        }
        if p.scissor && p.scope != Scope::Local {
            return Err(Error::Param(
                "scissor = on needs scope = local (only then are a map's pixels known)".into(),
            ));
        }
        // A preset names a setting; any parameter given beside it makes it another setting.
        if p.preset.is_some() && params.keys().any(|k| k != "preset") {
            p.preset = None;
        }
        Ok(p)
    }

    /// Whether new maps rasterize only the runs of triangles their tiles need (scope = local).
    pub(crate) fn culls(&self) -> bool {
        self.scope == Scope::Local && self.cull.unwrap_or(false)
    }

    /// Whether each map rasterizes only the triangles the footprint of every geometry pixel needs
    /// (scope = global, where every pixel tests every map: `methods::culled_maps`).
    pub(crate) fn culls_every_pixel(&self) -> bool {
        self.scope == Scope::Global && self.cull == Some(true)
    }

    /// Light coordinate (s or t, in [0, 1]) of lattice column or row `i` (0..=16). Lattice: i/16.
    /// Centred: the lattice inset by h = 1/(2n), n = 2^max_level + 1, so the points the quadtree can
    /// reach are the cell centres (m + ½)/n of the n×n grid (written that way, to match `regular`
    /// bit for bit).
    pub fn light_coord(&self, i: u32) -> f32 {
        match self.layout {
            Layout::Centred => {
                let n = (1u32 << self.max_level) + 1;
                if (i * (n - 1)) % 16 == 0 {
                    ((i * (n - 1) / 16) as f32 + 0.5) / n as f32
                } else {
                    let h = 0.5 / n as f64;
                    (h + i as f64 / 16.0 * (1.0 - 2.0 * h)) as f32
                }
            }
            _ => i as f32 / 16.0,
        }
    }

    /// Width of the border strip outside the inset lattice, in units of the lattice's side
    /// (half the finest spacing); 0 for the corner-to-corner lattice.
    pub(crate) fn border_strip(&self) -> f64 {
        match self.layout {
            Layout::Centred => 0.5 / (1u64 << self.max_level) as f64,
            _ => 0.0,
        }
    }

    /// The rule subdivide applies at `level` (the same function feeds the kernel and the twin).
    pub fn split_rule(&self, level: u32) -> SplitRule {
        match self.criterion {
            Criterion::Pixels { p_m, growth } => {
                if p_m < 0.0 {
                    return SplitRule::Always;
                }
                let t = p_m * growth.powi(level as i32);
                if t >= u32::MAX as f64 {
                    SplitRule::Never
                } else {
                    SplitRule::Threshold(t.floor() as u32)
                }
            }
            Criterion::Share { p_share, growth } => {
                SplitRule::Share((p_share * growth.powi(level as i32)) as f32)
            }
            Criterion::Tol { tol } => {
                let e = KAPPA * 0.25f64.powi(level as i32);
                SplitRule::Share(((tol / e) * (tol / e)) as f32)
            }
        }
    }

    pub(crate) fn label(&self) -> String {
        if let Some(preset) = self.preset {
            return format!(
                "adaptive:preset={}",
                if preset == Preset::Seed {
                    "seed"
                } else {
                    "balanced"
                }
            );
        }
        let mut s = match self.criterion {
            Criterion::Pixels { p_m, growth } => {
                format!("adaptive:p_m={p_m}{}", growth_label(growth))
            }
            Criterion::Share { p_share, growth } => {
                format!("adaptive:p_share={p_share}{}", growth_label(growth))
            }
            Criterion::Tol { tol } => format!("adaptive:tol={tol}"),
        };
        if self.max_level != 4 {
            s += &format!(",max_level={}", self.max_level);
        }
        match self.weights {
            // Local scope has one rule (area along each pixel's quads); naming it adds nothing.
            _ if self.scope == Scope::Local => {}
            Weights::Level => {}
            Weights::Area => s += ",weights=area",
            Weights::Coons => s += ",weights=coons",
        }
        if self.layout == Layout::Centred {
            s += ",layout=centred";
        }
        if self.scope == Scope::Local {
            s += ",scope=local";
        }
        if self.scissor {
            s += ",scissor=on";
        }
        if self.cull == Some(true) {
            s += ",cull=on";
        }
        if !self.steer_cpu {
            s += ",steer=gpu";
        }
        if let Some(n) = self.items {
            s += &format!(",items={n}");
        }
        if !self.items_grow {
            s += ",items_grow=off";
        }
        if self.hold != 0 {
            s += &format!(",hold={}", self.hold);
        }
        s
    }
}

fn growth_label(g: f64) -> String {
    if g == 1.0 {
        String::new()
    } else {
        format!(",growth={g}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(spec: &str) -> Result<AdaptiveParams> {
        let map: BTreeMap<String, String> = spec
            .split(',')
            .filter(|kv| !kv.is_empty())
            .map(|kv| {
                let (k, v) = kv.split_once('=').unwrap();
                (k.to_string(), v.to_string())
            })
            .collect();
        AdaptiveParams::from_map(&map)
    }

    #[test]
    fn local_scope_integrates_by_area_and_says_so() {
        let p = parse("preset=balanced,scope=local").unwrap();
        assert_eq!(p.weights, Weights::Area);
        assert_eq!(p.label(), "adaptive:p_m=0,max_level=3,scope=local");
        assert_eq!(
            parse("scope=local,weights=area").unwrap().weights,
            Weights::Area
        );
        for w in ["coons", "level"] {
            let e = parse(&format!("scope=local,weights={w}"))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(&format!("weights = `{w}`")) && e.contains("scope = local"),
                "{e}"
            );
        }
        assert_eq!(
            parse("preset=balanced").unwrap().label(),
            "adaptive:preset=balanced"
        );
        assert_eq!(
            parse("weights=coons,layout=centred").unwrap().label(),
            "adaptive:p_m=0,weights=coons,layout=centred"
        );
    }

    #[test]
    fn centred_coordinates_are_the_cell_centres() {
        for (max_level, n) in [(0u32, 2u32), (1, 3), (2, 5), (3, 9), (4, 17)] {
            let p = AdaptiveParams {
                max_level,
                layout: Layout::Centred,
                weights: Weights::Area,
                ..Default::default()
            };
            let step = 16 >> max_level;
            for m in 0..n {
                assert_eq!(
                    p.light_coord(m * step),
                    (m as f32 + 0.5) / n as f32,
                    "L {max_level} m {m}"
                );
            }
            assert_eq!(p.border_strip(), 0.5 / (1u32 << max_level) as f64);
        }
        let lattice = AdaptiveParams::default();
        assert_eq!(
            (
                lattice.light_coord(0),
                lattice.light_coord(16),
                lattice.border_strip()
            ),
            (0.0, 1.0, 0.0)
        );
    }
}
