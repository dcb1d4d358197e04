//! The oracle's candidates, what a per-region method could give a tile: culled centred grids
//! (n, map side), the single-map methods at each side, centred grids and the filters on hybrid
//! maps, and the adaptive presets; and each one's price from its own stage timings, split into
//! what a frame pays once (its maps) and what each tile pays (its pixel tests).

use crate::gpu::stages::{Split, Stage};
use crate::methods::{Family, Method};
use crate::studies::hybrid::Maps;
use crate::{Error, Result};
use std::collections::BTreeMap;

/// The default menu (docs/oracle.md).
pub const N: [u32; 8] = [1, 2, 3, 4, 6, 8, 11, 16];
pub const SIZES: [u32; 3] = [512, 1024, 2048];
pub const SINGLES: [&str; 3] = ["pcss", "pcf", "msm"];
pub const HYBRID: &str = "2048/2";
/// The adaptive presets by the names `--adaptive` takes, and their specs.
pub const ADAPTIVE: [(&str, &str); 4] = [
    ("seed", "adaptive:preset=seed"),
    ("balanced", "adaptive:preset=balanced"),
    ("seed-local", "adaptive:preset=seed,scope=local,cull=on"),
    (
        "balanced-local",
        "adaptive:preset=balanced,scope=local,cull=on",
    ),
];

/// What a candidate is; the menu `grids` holds only [`Kind::Grid`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A culled centred grid on plain maps.
    Grid,
    /// One map, filtered or not (`pcss`, `pcf`, `msm`, …).
    SingleMap,
    /// A centred grid or a filter on hybrid maps (uncut: hybrid maps are not culled).
    Hybrid,
    /// An adaptive preset in either scope.
    Adaptive,
}

impl Kind {
    pub fn name(self) -> &'static str {
        match self {
            Kind::Grid => "grid",
            Kind::SingleMap => "single map",
            Kind::Hybrid => "hybrid",
            Kind::Adaptive => "adaptive",
        }
    }
}

/// One candidate: a method spec under one map configuration.
#[derive(Clone, Debug)]
pub struct Candidate {
    pub spec: String,
    pub maps: Maps,
    pub kind: Kind,
    pub method: Method,
}

impl Candidate {
    /// A short name for tables and legends: `n=4@512`, `pcss@1024`, `n=4@h2048→512`,
    /// `balanced-local@512`.
    pub fn name(&self) -> String {
        let at = match self.maps {
            Maps::Plain(z) => z.to_string(),
            Maps::Hybrid { base, levels } => format!("h{base}→{}", base >> levels),
        };
        let what = if let Some((name, _)) = ADAPTIVE.iter().find(|(_, s)| *s == self.spec) {
            name.to_string()
        } else if let Some(n) = self.spec.strip_prefix("regular:n=") {
            format!("n={}", n.split(',').next().unwrap_or(n))
        } else {
            self.spec.clone()
        };
        format!("{what}@{at}")
    }
}

/// The menu's axes, as the flags give them.
#[derive(Clone, Debug)]
pub struct Menu {
    pub n: Vec<u32>,
    pub sizes: Vec<u32>,
    pub singles: Vec<String>,
    pub hybrid: Vec<Maps>,
    /// Names of [`ADAPTIVE`].
    pub adaptive: Vec<String>,
}

/// `--singles pcss,pcf`: methods of one map (`penumbra methods`: the hard, pcf and filtered
/// families), or `none`.
pub fn parse_singles(values: &[String]) -> Result<Vec<String>> {
    if values.len() == 1 && values[0].trim() == "none" {
        return Ok(Vec::new());
    }
    let names: Vec<String> = values.iter().map(|v| v.trim().to_string()).collect();
    for v in &names {
        let ok = crate::methods::REGISTRY.iter().any(|m| {
            m.name == v && matches!(m.family, Family::Hard | Family::Pcf | Family::Filtered)
        });
        if !ok {
            return Err(Error::param(format!("--singles `{v}`: not a method of one map (hard, pcf, pcss, esm, vsm, evsm, msm, csm; or none)")));
        }
    }
    crate::studies::lists::listed_once("--singles", values.iter().zip(names.iter().cloned()))?;
    Ok(names)
}

/// `--adaptive seed,balanced-local`: names of [`ADAPTIVE`], or `none`.
pub fn parse_adaptive(values: &[String]) -> Result<Vec<String>> {
    if values.len() == 1 && values[0].trim() == "none" {
        return Ok(Vec::new());
    }
    let names: Vec<String> = values.iter().map(|v| v.trim().to_string()).collect();
    if let Some(v) = names.iter().find(|v| !ADAPTIVE.iter().any(|(n, _)| n == v)) {
        let known: Vec<&str> = ADAPTIVE.iter().map(|(n, _)| *n).collect();
        return Err(Error::param(format!(
            "--adaptive `{v}`: not a preset ({}; or none)",
            known.join(", ")
        )));
    }
    crate::studies::lists::listed_once("--adaptive", values.iter().zip(names.iter().cloned()))?;
    Ok(names)
}

/// The candidates of one map configuration.
#[derive(Clone, Debug)]
pub struct Group {
    pub maps: Maps,
    pub candidates: Vec<Candidate>,
}

/// Every candidate of the menu, grouped by map configuration (plain sides in order, then hybrid):
/// on plain maps the culled centred grids, the single-map methods and the adaptive presets
/// (local scope only where its 289 maps fit the map budget, else left out and named in `left`);
/// on hybrid maps the centred grids and the single-map methods that read them.
pub fn groups(menu: &Menu, budget_mib: u32) -> Result<(Vec<Group>, Vec<String>)> {
    let mut out = Vec::new();
    let mut left = Vec::new();
    let parse = |spec: &str| Method::parse(spec, &[]);
    for &z in &menu.sizes {
        let mut c = Vec::new();
        for n in &menu.n {
            let spec = format!("regular:n={n},layout=centred,cull=on");
            c.push(Candidate {
                method: parse(&spec)?,
                spec,
                maps: Maps::Plain(z),
                kind: Kind::Grid,
            });
        }
        for s in &menu.singles {
            c.push(Candidate {
                method: parse(s)?,
                spec: s.clone(),
                maps: Maps::Plain(z),
                kind: Kind::SingleMap,
            });
        }
        for name in &menu.adaptive {
            let spec = ADAPTIVE
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, s)| s.to_string())
                .expect("parsed names are presets");
            if spec.contains("scope=local")
                && !crate::studies::frontier::grid::local_fits(z, budget_mib)
            {
                left.push(format!(
                    "{name}@{z}: 289 maps of {z}² do not fit shadow_map_budget_mib = {budget_mib}"
                ));
                continue;
            }
            c.push(Candidate {
                method: parse(&spec)?,
                spec,
                maps: Maps::Plain(z),
                kind: Kind::Adaptive,
            });
        }
        out.push(Group {
            maps: Maps::Plain(z),
            candidates: c,
        });
    }
    for &maps in &menu.hybrid {
        let mut c = Vec::new();
        for n in &menu.n {
            let spec = format!("regular:n={n},layout=centred");
            c.push(Candidate {
                method: parse(&spec)?,
                spec,
                maps,
                kind: Kind::Hybrid,
            });
        }
        for s in menu
            .singles
            .iter()
            .filter(|s| matches!(Family::of_name(s), Family::Hard | Family::Pcf))
        {
            c.push(Candidate {
                method: parse(s)?,
                spec: s.clone(),
                maps,
                kind: Kind::Hybrid,
            });
        }
        out.push(Group {
            maps,
            candidates: c,
        });
    }
    Ok((out, left))
}

/// Candidates in all groups.
pub fn count(groups: &[Group]) -> usize {
    groups.iter().map(|g| g.candidates.len()).sum()
}

/// Where a stage's time goes in the oracle's frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Every frame pays it once, whatever it chooses: the G-buffer and the read-back.
    Fixed,
    /// The candidate's maps and what prepares them (cull, raster, moments, hybrid build): paid
    /// once per frame by a candidate any tile uses.
    Maps,
    /// Work per pixel (the tests that make V, the culling footprint, the adaptive decision): each
    /// tile pays its pixels' share. Charging a stage here rather than to the maps can only lower
    /// the oracle's price, so a stage the table does not know comes here too: the bound stays a
    /// bound.
    Tests,
}

pub fn part(stage: &str) -> Part {
    match Stage::named(stage) {
        Some(s) if s == Stage::GBUFFER => Part::Fixed,
        Some(s) if s == Stage::FOOTPRINT => Part::Tests,
        Some(Stage {
            split: Some(Split::Raster),
            ..
        }) => Part::Maps,
        Some(Stage {
            split: Some(Split::Waits),
            ..
        }) => Part::Fixed,
        _ => Part::Tests,
    }
}

/// A candidate's price: the stages-mode frame's split, scaled so that the three parts add up to
/// the median of its timed frames (the stages frame waits after every stage; its shares are
/// kept, its total is one frame's).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Price {
    pub fixed_ms: f64,
    pub maps_ms: f64,
    /// Every geometry pixel's tests together.
    pub tests_ms: f64,
}

impl Price {
    pub fn of(stages_ms: &BTreeMap<String, f64>, median_ms: f64) -> Price {
        let mut p = Price::default();
        for (name, &ms) in stages_ms {
            match part(name) {
                Part::Fixed => p.fixed_ms += ms,
                Part::Maps => p.maps_ms += ms,
                Part::Tests => p.tests_ms += ms,
            }
        }
        let total = p.fixed_ms + p.maps_ms + p.tests_ms;
        let k = if total > 0.0 && median_ms.is_finite() {
            median_ms / total
        } else {
            1.0
        };
        Price {
            fixed_ms: p.fixed_ms * k,
            maps_ms: p.maps_ms * k,
            tests_ms: p.tests_ms * k,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stages_split_into_fixed_maps_and_tests() {
        for (stage, want) in [
            ("gbuffer", Part::Fixed),
            ("readback", Part::Fixed),
            ("cull", Part::Maps),
            ("shadow_raster", Part::Maps),
            ("moments", Part::Maps),
            ("hybrid_build", Part::Maps),
            ("footprint", Part::Tests),
            ("shade", Part::Tests),
            ("pcss", Part::Tests),
            ("reproject_count", Part::Tests),
            ("shadow_test", Part::Tests),
            ("no_such_stage", Part::Tests),
        ] {
            assert_eq!(part(stage), want, "{stage}");
        }
        // A grid's stages-mode frame (canopy-market, 128², n = 6 at 512²), scaled to its median.
        let stages: BTreeMap<String, f64> = [
            ("cull", 9.7),
            ("footprint", 28.9),
            ("gbuffer", 2.1),
            ("readback", 0.3),
            ("shade", 22.9),
            ("shadow_raster", 25.6),
        ]
        .iter()
        .map(|(k, v)| (k.to_string(), *v))
        .collect();
        let p = Price::of(&stages, 2.0 * 89.5);
        assert!(
            (p.fixed_ms - 4.8).abs() < 1e-9
                && (p.maps_ms - 70.6).abs() < 1e-9
                && (p.tests_ms - 103.6).abs() < 1e-9,
            "{p:?}"
        );
    }

    #[test]
    fn the_default_menu() {
        let menu = Menu {
            n: N.to_vec(),
            sizes: SIZES.to_vec(),
            singles: SINGLES.iter().map(|s| s.to_string()).collect(),
            hybrid: vec![crate::studies::hybrid::parse_maps(HYBRID, true).unwrap()],
            adaptive: ADAPTIVE.iter().map(|(n, _)| n.to_string()).collect(),
        };
        let (groups, left) = groups(&menu, 512).unwrap();
        // Per plain side 8 grids, 3 filters, 2 global presets (+2 local at 512²); hybrid: 8 grids, pcss, pcf.
        assert_eq!(
            groups
                .iter()
                .map(|g| g.candidates.len())
                .collect::<Vec<_>>(),
            [15, 13, 13, 10]
        );
        assert_eq!(left.len(), 4, "{left:?}");
        let names: Vec<String> = groups
            .iter()
            .flat_map(|g| g.candidates.iter().map(Candidate::name))
            .collect();
        for want in [
            "n=1@512",
            "n=16@2048",
            "pcss@1024",
            "msm@2048",
            "balanced-local@512",
            "seed@2048",
            "n=4@h2048→512",
            "pcf@h2048→512",
        ] {
            assert!(names.iter().any(|n| n == want), "{want} in {names:?}");
        }
        assert!(
            !names.iter().any(|n| n.starts_with("msm@h")),
            "msm reads no hybrid maps"
        );
        assert!(parse_singles(&["pcss".into(), "regular".into()])
            .unwrap_err()
            .to_string()
            .starts_with("--singles `regular`: not a method of one map"));
        assert!(parse_adaptive(&["fast".into()])
            .unwrap_err()
            .to_string()
            .starts_with("--adaptive `fast`: not a preset (seed, balanced"));
        assert!(parse_adaptive(&["none".into()]).unwrap().is_empty());
    }
}
