//! Adaptive method parameters (`adaptive:p_m=0,scope=local`, or `penumbra render --param p_m=0`).

use super::super::{Layout, OptionalDecl, Param, ParamDecl, ParamMap, SwitchDecl, WordDecl};
use crate::{Error, Result};
use serde::Serialize;

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

/// The declared defaults (`penumbra methods` lists them): the parameters parsed with none given.
impl Default for AdaptiveParams {
    fn default() -> Self {
        // Every declared default parses (params::tests and param_decl's test over all of them).
        Self::from_map(&ParamMap::new()).expect("the adaptive method's declared defaults parse")
    }
}

/// The method's name in the range messages.
const METHOD: &str = "adaptive";

/// The balanced preset beside the declared defaults, as a spec writes it, and as the listing's
/// help quotes it (a macro so that `concat!` can). Chosen from measurements
/// (results/bench-fair-baselines/, "Choosing `balanced`"): the seed's zero threshold, no split
/// below level 3 (at the seed's 512² maps the maps' own error dominates past the 9x9 lattice),
/// Coons weights, global scope.
macro_rules! balanced {
    () => {
        "max_level=3,weights=coons"
    };
}

pub(crate) const PRESET: WordDecl<Preset> = WordDecl::new(
    "preset",
    "none",
    &[("seed", Preset::Seed), ("balanced", Preset::Balanced)],
    concat!(
        "seed (the seed's settings: the defaults) or balanced (",
        balanced!(),
        "; results/bench-fair-baselines/)"
    ),
);
pub(crate) const P_M: ParamDecl<f64> = ParamDecl::new(
    "p_m",
    "0",
    f64::NEG_INFINITY,
    f64::INFINITY,
    "split when a quad's low-quality pixels exceed p_m (-1 always, inf never)",
);
pub(crate) const P_SHARE: OptionalDecl<f64> = OptionalDecl::new(
    "p_share",
    "none",
    0.0,
    1.0,
    "split threshold as a share of the geometry pixels, 0..=1 (instead of p_m)",
)
.why("a share of the geometry pixels, in [0, 1]");
pub(crate) const GROWTH: ParamDecl<f64> = ParamDecl::new(
    "growth",
    "1",
    1.0,
    1e6,
    "threshold factor per level for p_m or p_share, 1..=1e6",
)
.why("the level factor must be in [1, 1e6]");
/// Positive and finite: the smallest positive f64 up to the largest finite one.
pub(crate) const TOL: OptionalDecl<f64> = OptionalDecl::new(
    "tol",
    "none",
    f64::from_bits(1),
    f64::MAX,
    "error budget: split when a quad's estimated RMSE exceeds tol (instead of p_m)",
)
.why("the error budget must be a positive finite RMSE");
pub(crate) const MAX_LEVEL: ParamDecl<u32> = ParamDecl::new(
    "max_level",
    "4",
    0,
    4,
    "deepest quadtree level, 0..=4 (4 = the 17×17 lattice)",
)
.why("use 0..=4, the lattice of docs/method.md §3 (L_max = 4, 17x17 points)");
pub(crate) const WEIGHTS: WordDecl<Weights> = WordDecl::new(
    "weights",
    "level",
    &[
        ("level", Weights::Level),
        ("area", Weights::Area),
        ("coons", Weights::Coons),
    ],
    "sample weights: level (the seed's 1/(2^l+1)²), area or coons",
);
pub(crate) const SCOPE: WordDecl<Scope> = WordDecl::new(
    "scope",
    "global",
    &[("global", Scope::Global), ("local", Scope::Local)],
    "global (every map shades every pixel) or local (region-local refinement)",
);
/// `centered` is read as `centred`; `jittered` (regular's) is refused with its own reason.
pub(crate) const LAYOUT: WordDecl<Layout> = WordDecl::new(
    "layout",
    "lattice",
    &[("lattice", Layout::Lattice), ("centred", Layout::Centred)],
    "lattice (the seed: corner to corner) or centred (inset half a finest cell: the midpoint rule when fully split; global scope)",
);
pub(crate) const SCISSOR: SwitchDecl = SwitchDecl::new(
    "scissor",
    false,
    "scope=local only: raster each map only over the texels its pixels test",
)
.or_true_false();
/// The value is `steer_cpu`.
pub(crate) const STEER: WordDecl<bool> = WordDecl::new(
    "steer",
    "cpu",
    &[("gpu", false), ("cpu", true)],
    "cpu: one read-back per level; gpu: the levels drive each other on the GPU, no read-back (scope=global on the lattice layout, or scope=local without scissor or cull; slower on an H100 today, results/bench-seed-table2-h100/)",
);
/// Left out it is recorded as unset (`"cull": null`), which runs as `off`.
pub(crate) const CULL: SwitchDecl = SwitchDecl::new(
    "cull",
    false,
    "raster each map only with the triangles that can change a texel its pixels test (scope=local: the pixels that test it; scope=global: every geometry pixel); the same V (docs/gpu-frame.md)",
)
.or_true_false();
pub(crate) const ITEMS: OptionalDecl<u32> = OptionalDecl::new(
    "items",
    "32 per pixel",
    1,
    u32::MAX,
    "scope=local only: the (pixel, quad) item list's starting capacity, at most what one binding holds; a frame that overflows it runs again on a list grown from the count",
)
.why("use a whole number of items, at least 1");
pub(crate) const HOLD: ParamDecl<u32> = ParamDecl::new(
    "hold",
    "0",
    0,
    u32::MAX,
    "hysteresis in low-quality pixels: a quad the previous frame did not split needs this many more to split; one it split stays split down to the threshold (docs/reuse.md)",
);
pub(crate) const ITEMS_GROW: SwitchDecl = SwitchDecl::new(
    "items_grow",
    true,
    "scope=local only: off fails a frame that overflows the item list (reported, never clipped) instead of growing it",
)
.or_true_false();

/// The listing, in the order `penumbra methods adaptive` prints it.
pub(crate) const LISTED: &[Param] = &[
    PRESET.param(),
    P_M.param(),
    P_SHARE.param(),
    GROWTH.param(),
    TOL.param(),
    MAX_LEVEL.param(),
    WEIGHTS.param(),
    SCOPE.param(),
    LAYOUT.param(),
    SCISSOR.param(),
    STEER.param(),
    CULL.param(),
    ITEMS.param(),
    HOLD.param(),
    ITEMS_GROW.param(),
];

impl Preset {
    /// The settings a preset stands for beside the declared defaults (`seed`: none).
    fn settings(self) -> ParamMap {
        let spec = match self {
            Preset::Seed => "",
            Preset::Balanced => balanced!(),
        };
        spec.split(',')
            .filter_map(|kv| kv.split_once('='))
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    }
}

impl AdaptiveParams {
    /// The parameters `given` name, each read through its declaration; a preset's settings stand
    /// under the given ones, as if written before them.
    pub(crate) fn from_map(given: &ParamMap) -> Result<Self> {
        let preset = PRESET.given(given)?;
        let mut p = preset.map(Preset::settings).unwrap_or_default();
        p.extend(given.iter().map(|(k, v)| (k.clone(), v.clone())));
        let criteria: Vec<&str> = [P_M.key, P_SHARE.key(), TOL.key()]
            .into_iter()
            .filter(|k| p.contains_key(*k))
            .collect();
        if criteria.len() > 1 {
            return Err(Error::Param(format!(
                "adaptive: give one split criterion, not {}",
                criteria.join(" and ")
            )));
        }
        let growth = GROWTH.get(&p, METHOD)?;
        let criterion = if let Some(tol) = TOL.get(&p, METHOD)? {
            if p.contains_key(GROWTH.key) {
                return Err(Error::Param(
                    "growth applies to p_m or p_share; tol sets its own level factor (16)".into(),
                ));
            }
            Criterion::Tol { tol }
        } else if let Some(p_share) = P_SHARE.get(&p, METHOD)? {
            Criterion::Share { p_share, growth }
        } else {
            Criterion::Pixels {
                p_m: P_M.get(&p, METHOD)?,
                growth,
            }
        };
        let max_level = MAX_LEVEL.get(&p, METHOD)?;
        let mut weights = WEIGHTS.get(&p)?;
        let scope = SCOPE.get(&p)?;
        // Local scope sums each pixel's own leaf quads by area (docs/method.md §4.2); it has no use
        // for sample weights, so a preset's weights become area there and others are refused.
        if scope == Scope::Local {
            match given.get(WEIGHTS.key).map(String::as_str) {
                None | Some("area") => weights = Weights::Area,
                Some(v) => {
                    return Err(Error::Param(format!(
                        "weights = `{v}` applies to scope = global; scope = local integrates each pixel's own quads by area (use weights=area or leave it out)"
                    )))
                }
            }
        }
        let scissor = SCISSOR.get(&p, METHOD)?;
        let cull = CULL.given(&p, METHOD)?;
        let steer_cpu = STEER.get(&p)?;
        let items = ITEMS.get(&p, METHOD)?;
        if items.is_some() && scope != Scope::Local {
            return Err(Error::Param(
                "adaptive: items needs scope = local (only it keeps an item list)".into(),
            ));
        }
        let items_grow = ITEMS_GROW.get(&p, METHOD)?;
        if p.contains_key(ITEMS_GROW.key) && scope != Scope::Local {
            return Err(Error::Param(
                "adaptive: items_grow needs scope = local (only it keeps an item list)".into(),
            ));
        }
        let hold = HOLD.get(&p, METHOD)?;
        let layout = match p.get(LAYOUT.key).map(String::as_str) {
            Some("centered") => Layout::Centred,
            Some("jittered") => return Err(Error::Param("adaptive: layout = `jittered`: the quadtree needs nested samples; use `lattice` or `centred`".into())),
            _ => LAYOUT.get(&p)?,
        };
        if layout == Layout::Centred && scope == Scope::Local {
            return Err(Error::Param("adaptive: layout = centred needs scope = global (local scope counts uniform quad shares; the border strips are not uniform)".into()));
        }
        if layout == Layout::Centred && weights == Weights::Level {
            return Err(Error::Param("adaptive: layout = centred needs weights = area or coons (the level rule has no border strips)".into()));
        }
        if scissor && scope != Scope::Local {
            return Err(Error::Param(
                "scissor = on needs scope = local (only then are a map's pixels known)".into(),
            ));
        }
        Ok(Self {
            // A preset names a setting; any parameter given beside it makes it another setting.
            preset: preset.filter(|_| given.keys().all(|k| k == PRESET.key)),
            criterion,
            max_level,
            weights,
            scope,
            scissor,
            cull,
            steer_cpu,
            layout,
            items,
            items_grow,
            hold,
        })
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

    /// `adaptive:preset=…`, or the criterion and every parameter whose value differs from the
    /// listed default, in the listing's order.
    pub(crate) fn label(&self) -> String {
        if let Some(word) = self.preset.and_then(|p| PRESET.word(p)) {
            return format!("adaptive:{}={word}", PRESET.key);
        }
        let growth = |g: f64| {
            let g = g.to_string();
            if g == GROWTH.default {
                String::new()
            } else {
                format!(",{}={g}", GROWTH.key)
            }
        };
        let mut s = match self.criterion {
            Criterion::Pixels { p_m, growth: g } => format!("adaptive:p_m={p_m}{}", growth(g)),
            Criterion::Share { p_share, growth: g } => {
                format!("adaptive:p_share={p_share}{}", growth(g))
            }
            Criterion::Tol { tol } => format!("adaptive:tol={tol}"),
        };
        let word = |w: Option<&str>| w.map(str::to_string);
        let on_off = |on: bool| Some(if on { "on" } else { "off" }.to_string());
        // Local scope has one rule (area along each pixel's quads): naming it adds nothing.
        let weights = word(WEIGHTS.word(self.weights)).filter(|_| self.scope != Scope::Local);
        let values = [
            (MAX_LEVEL.param(), Some(self.max_level.to_string())),
            (WEIGHTS.param(), weights),
            (LAYOUT.param(), word(LAYOUT.word(self.layout))),
            (SCOPE.param(), word(SCOPE.word(self.scope))),
            (SCISSOR.param(), on_off(self.scissor)),
            (CULL.param(), self.cull.and_then(on_off)),
            (STEER.param(), word(STEER.word(self.steer_cpu))),
            (ITEMS.param(), self.items.map(|n| n.to_string())),
            (ITEMS_GROW.param(), on_off(self.items_grow)),
            (HOLD.param(), Some(self.hold.to_string())),
        ];
        for (param, value) in values {
            if let Some(v) = value.filter(|v| v != param.default) {
                s += &format!(",{}={v}", param.key);
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(spec: &str) -> Result<AdaptiveParams> {
        let map: ParamMap = spec
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
    fn the_defaults_and_the_presets_are_their_declarations() {
        let d = AdaptiveParams::default();
        assert_eq!(
            d.criterion,
            Criterion::Pixels {
                p_m: 0.0,
                growth: 1.0
            }
        );
        assert_eq!(
            (d.max_level, d.weights, d.scope, d.layout),
            (4, Weights::Level, Scope::Global, Layout::Lattice)
        );
        assert_eq!(
            (d.preset, d.scissor, d.cull, d.steer_cpu),
            (None, false, None, true)
        );
        assert_eq!((d.items, d.items_grow, d.hold), (None, true, 0));
        assert_eq!(d.label(), "adaptive:p_m=0");
        // seed is the defaults; balanced is its settings, as the listing quotes them.
        let seed = parse("preset=seed").unwrap();
        assert_eq!(seed.preset, Some(Preset::Seed));
        assert_eq!(
            AdaptiveParams {
                preset: None,
                ..seed
            },
            d
        );
        let balanced = parse("preset=balanced").unwrap();
        assert_eq!((balanced.max_level, balanced.weights), (3, Weights::Coons));
        assert_eq!(
            AdaptiveParams {
                preset: Some(Preset::Balanced),
                ..parse(balanced!()).unwrap()
            },
            balanced
        );
        assert!(PRESET.help.contains(balanced!()), "{}", PRESET.help);
        // A parameter given beside a preset overrides the preset's and names another setting.
        let p = parse("preset=balanced,max_level=2").unwrap();
        assert_eq!(
            (p.preset, p.max_level, p.weights),
            (None, 2, Weights::Coons)
        );
        assert_eq!(p.label(), "adaptive:p_m=0,max_level=2,weights=coons");
    }

    #[test]
    fn bad_values_are_refused_with_the_key_the_value_and_why() {
        for (spec, message) in [
            ("preset=none", "preset = `none`: use `seed` or `balanced`"),
            ("p_m=banana", "parameter p_m = `banana` is not a number"),
            ("p_m=nan", "parameter p_m = `nan` must not be NaN"),
            ("p_m=1,p_share=0.1", "adaptive: give one split criterion, not p_m and p_share"),
            ("growth=0.5", "adaptive: growth = `0.5`: the level factor must be in [1, 1e6]"),
            ("growth=abc", "adaptive: growth = `abc`: the level factor must be in [1, 1e6]"),
            ("p_share=2", "adaptive: p_share = `2`: a share of the geometry pixels, in [0, 1]"),
            ("tol=0", "adaptive: tol = `0`: the error budget must be a positive finite RMSE"),
            ("tol=inf", "adaptive: tol = `inf`: the error budget must be a positive finite RMSE"),
            ("tol=0.01,growth=2", "growth applies to p_m or p_share; tol sets its own level factor (16)"),
            ("max_level=5", "adaptive: max_level = `5`: use 0..=4, the lattice of docs/method.md §3 (L_max = 4, 17x17 points)"),
            ("weights=x", "weights = `x`: use `level`, `area` or `coons`"),
            ("scope=x", "scope = `x`: use `global` or `local`"),
            ("scissor=x", "adaptive: scissor = `x`: use `on` or `off`"),
            ("scissor=on", "scissor = on needs scope = local (only then are a map's pixels known)"),
            ("cull=x", "adaptive: cull = `x`: use `on` or `off`"),
            ("steer=x", "steer = `x`: use `gpu` or `cpu`"),
            ("scope=local,items=0", "adaptive: items = `0`: use a whole number of items, at least 1"),
            ("scope=local,items=-1", "adaptive: items = `-1`: use a whole number of items, at least 1"),
            ("items=100", "adaptive: items needs scope = local (only it keeps an item list)"),
            ("items_grow=off", "adaptive: items_grow needs scope = local (only it keeps an item list)"),
            ("hold=-1", "parameter hold = `-1` is not a non-negative integer"),
            ("layout=jittered", "adaptive: layout = `jittered`: the quadtree needs nested samples; use `lattice` or `centred`"),
            ("layout=x", "layout = `x`: use `lattice` or `centred`"),
            ("layout=centred", "adaptive: layout = centred needs weights = area or coons (the level rule has no border strips)"),
        ] {
            let e = parse(spec).unwrap_err().to_string();
            assert_eq!(e, message, "{spec}");
        }
        // What is taken: the infinities, the least positive tol, `centered`, `true` and `false`.
        assert_eq!(parse("p_m=-inf").unwrap().split_rule(2), SplitRule::Always);
        assert_eq!(parse("p_m=inf").unwrap().split_rule(0), SplitRule::Never);
        assert!(parse("tol=1e-320").is_ok());
        assert_eq!(
            parse("layout=centered,weights=area").unwrap().layout,
            Layout::Centred
        );
        let p = parse("scope=local,scissor=true,cull=false,items_grow=true").unwrap();
        assert_eq!((p.scissor, p.cull, p.items_grow), (true, Some(false), true));
        assert_eq!(p.label(), "adaptive:p_m=0,scope=local,scissor=on");
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
