//! The frontier's settings: every fixed setting of a scene, as (method spec, map configuration)
//! pairs, the full grid or a thinned one (docs/frontier.md).

use crate::methods::{Family, Method};
use crate::studies::hybrid::{parse_maps, Maps};
use crate::studies::lists::listed_once;
use crate::{Error, Result};

/// `n` of the full grid: every regular grid from 2×2 to the 17×17 lattice.
pub const FULL_N: [u32; 16] = [2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17];
/// Plain map sizes of the full grid.
pub const FULL_SIZES: [u32; 4] = [256, 512, 1024, 2048];
/// The thinned grid: about every √2 step of n (each a third to half more maps than the last), and
/// the two middle map sizes, where the 1 M-triangle scenes' settings fall.
pub const THIN_N: [u32; 8] = [2, 3, 4, 5, 6, 8, 11, 17];
pub const THIN_SIZES: [u32; 2] = [512, 1024];
/// Scenes of at least this many triangles get the thinned grid unless `--full` is given: a
/// 17×17 frame at 2048² on the 1 M-triangle dragon takes minutes on a CPU device.
pub const AUTO_THIN_TRIANGLES: usize = 500_000;
/// Hybrid maps of the grid: the seed's 2048² merged to 512² on smooth surfaces.
pub const DEFAULT_HYBRID: &str = "2048/2";

/// The single-map family: one map each, filtered or not (`penumbra methods`).
pub const SINGLE_MAP: [&str; 8] = ["hard", "pcf", "pcss", "esm", "vsm", "evsm", "msm", "csm"];
/// The adaptive presets, each in both scopes (local: region-local refinement with culling).
pub const ADAPTIVE: [&str; 4] = [
    "adaptive:preset=seed",
    "adaptive:preset=balanced",
    "adaptive:preset=seed,scope=local,cull=on",
    "adaptive:preset=balanced,scope=local,cull=on",
];

/// How the grid was chosen; recorded in every line of `frontier.jsonl`.
#[derive(Clone, Debug, PartialEq)]
pub enum Thinning {
    Full,
    /// `--thin`.
    Asked,
    /// The scene has this many triangles (at least [`AUTO_THIN_TRIANGLES`]).
    Automatic(usize),
}

impl Thinning {
    /// The choice and the axes actually run (`--n`, `--sizes` and `--hybrid` may replace them).
    pub fn describe(&self, axes: &Axes) -> String {
        let how = match self {
            Thinning::Full => "full grid".to_string(),
            Thinning::Asked => "thinned grid (--thin)".to_string(),
            Thinning::Automatic(t) => {
                format!("thinned grid (automatic: {t} triangles, at least {AUTO_THIN_TRIANGLES})")
            }
        };
        let hybrid: Vec<String> = axes.hybrid.iter().map(Maps::label).collect();
        // `--cull` changes every plain grid's time, so the line that describes the grid says so.
        let cull = if axes.cull {
            "; the plain maps' regular grids culled (--cull)"
        } else {
            ""
        };
        format!(
            "{how}: n in {:?}, plain maps {:?}, hybrid maps [{}]{cull}",
            axes.n,
            axes.sizes,
            hybrid.join(", ")
        )
    }

    pub fn choose(thin: bool, full: bool, triangles: usize) -> Result<Thinning> {
        match (thin, full) {
            (true, true) => Err(Error::param(
                "--thin and --full: give one or the other".into(),
            )),
            (true, false) => Ok(Thinning::Asked),
            (false, true) => Ok(Thinning::Full),
            (false, false) if triangles >= AUTO_THIN_TRIANGLES => {
                Ok(Thinning::Automatic(triangles))
            }
            (false, false) => Ok(Thinning::Full),
        }
    }
}

/// The grid's axes. `--n` and `--sizes` replace the thinning's lists (recorded as given).
#[derive(Clone, Debug)]
pub struct Axes {
    pub n: Vec<u32>,
    pub sizes: Vec<u32>,
    /// Hybrid map configurations (`BASE/LEVELS`); empty for none.
    pub hybrid: Vec<Maps>,
    /// `--cull`: the regular grids on plain maps rasterize each map with only the triangles that
    /// can change a tested texel (`cull = on`, the same V), as `regions` does.
    pub cull: bool,
}

impl Axes {
    pub fn of(thinning: &Thinning) -> Axes {
        let hybrid = vec![parse_maps(DEFAULT_HYBRID, true).expect("the default hybrid maps parse")];
        match thinning {
            Thinning::Full => Axes {
                n: FULL_N.to_vec(),
                sizes: FULL_SIZES.to_vec(),
                hybrid,
                cull: false,
            },
            _ => Axes {
                n: THIN_N.to_vec(),
                sizes: THIN_SIZES.to_vec(),
                hybrid,
                cull: false,
            },
        }
    }
}

/// `--n 2,3,5`: each in 1..=128 (regular's range), no repeats.
pub fn parse_n(values: &[String]) -> Result<Vec<u32>> {
    let mut out = Vec::new();
    for v in values {
        let n: i64 = v
            .trim()
            .parse()
            .map_err(|_| Error::param(format!("--n `{v}`: not a whole number")))?;
        if !(1..=128).contains(&n) {
            return Err(Error::param(format!("--n `{v}`: n must be in 1..=128")));
        }
        out.push(n as u32);
    }
    if out.is_empty() {
        return Err(Error::param("--n: no value given".into()));
    }
    listed_once("--n", values.iter().zip(out.iter().copied()))?;
    Ok(out)
}

/// `--sizes 512,1024`: plain map sizes as `hybrid` parses them (8..=16384), no repeats.
pub fn parse_sizes(values: &[String]) -> Result<Vec<u32>> {
    let mut out = Vec::new();
    for v in values {
        let Maps::Plain(size) =
            parse_maps(v, false).map_err(|e| Error::param(format!("--sizes: {e}")))?
        else {
            unreachable!("plain sizes parse as plain maps")
        };
        out.push(size);
    }
    if out.is_empty() {
        return Err(Error::param("--sizes: no value given".into()));
    }
    listed_once("--sizes", values.iter().zip(out.iter().copied()))?;
    Ok(out)
}

/// `--hybrid 2048/2,1024/1`; `none` for no hybrid maps.
pub fn parse_hybrid(values: &[String]) -> Result<Vec<Maps>> {
    if values.len() == 1 && values[0].trim() == "none" {
        return Ok(Vec::new());
    }
    let maps = values
        .iter()
        .map(|v| parse_maps(v, true).map_err(|e| Error::param(format!("--hybrid: {e}"))))
        .collect::<Result<Vec<_>>>()?;
    listed_once("--hybrid", values.iter().zip(maps.iter().copied()))?;
    Ok(maps)
}

/// One fixed setting: a method under one map configuration.
#[derive(Clone, Debug)]
pub struct Setting {
    pub method: Method,
    pub maps: Maps,
}

/// Methods that read hybrid maps (docs/hybrid.md): the single-map tests and global-scope
/// multi-map methods; prefiltered maps and local scope refuse them.
fn reads_hybrid(m: &Method) -> bool {
    match m.family() {
        Family::Filtered => false,
        _ => m
            .adaptive_params()
            .is_none_or(|p| p.scope == crate::methods::Scope::Global),
    }
}

/// The method specs run under every map configuration: regular grids (lattice, then centred),
/// the adaptive presets, the single-map family.
pub fn method_specs(n: &[u32]) -> Vec<String> {
    let mut specs: Vec<String> = n.iter().map(|n| format!("regular:n={n}")).collect();
    specs.extend(n.iter().map(|n| format!("regular:n={n},layout=centred")));
    specs.extend(ADAPTIVE.iter().map(|s| s.to_string()));
    specs.extend(SINGLE_MAP.iter().map(|s| s.to_string()));
    specs
}

/// Every setting, grouped by map configuration (plain sizes in order, then hybrid), methods in
/// [`method_specs`] order; hybrid groups hold only the methods that read hybrid maps.
pub fn settings(axes: &Axes, budget_mib: u32) -> Result<Vec<Group>> {
    let specs = method_specs(&axes.n);
    let methods = crate::studies::compare::methods_list::parse_methods(&specs)?;
    // Culling rasterizes plain maps only: the hybrid groups keep the uncut grids.
    let plain_specs: Vec<String> = if axes.cull {
        specs
            .iter()
            .map(|s| {
                if s.starts_with("regular:") {
                    format!("{s},cull=on")
                } else {
                    s.clone()
                }
            })
            .collect()
    } else {
        specs.clone()
    };
    let plain_methods = crate::studies::compare::methods_list::parse_methods(&plain_specs)?;
    let mut groups: Vec<Group> = Vec::new();
    for &size in &axes.sizes {
        let keep = |m: &Method| {
            local_fits(size, budget_mib)
                || m.adaptive_params()
                    .is_none_or(|p| p.scope == crate::methods::Scope::Global)
        };
        let (specs, methods) = plain_specs
            .iter()
            .zip(&plain_methods)
            .filter(|(_, m)| keep(m))
            .map(|(s, m)| (s.clone(), m.clone()))
            .unzip();
        groups.push(Group {
            maps: Maps::Plain(size),
            specs,
            methods,
        });
    }
    for &maps in &axes.hybrid {
        let (specs, methods) = specs
            .iter()
            .zip(&methods)
            .filter(|(_, m)| reads_hybrid(m))
            .map(|(s, m)| (s.clone(), m.clone()))
            .unzip();
        groups.push(Group {
            maps,
            specs,
            methods,
        });
    }
    Ok(groups)
}

/// Leaves out the settings that `check` refuses under their map configuration, so one refusal
/// does not stop the whole grid: the methods that refuse the scene's light (docs/lights.md lists
/// the pairs: local scope keeps one map per light point, which a point light's six cube faces do
/// not allow, and a point light's cube maps, which the hybrid store cannot hold), and the frames
/// over the device's limits (the prefiltered maps' moments at 4096²). Returns each refused
/// `spec @ maps` with the reason.
pub fn drop_refused(
    groups: &mut [Group],
    scene: &crate::scene::Scene,
    check: impl Fn(&crate::scene::Scene, &Method) -> Result<()>,
) -> Vec<(String, String)> {
    let mut refused: Vec<(String, String)> = Vec::new();
    for g in groups.iter_mut() {
        let under = g.maps.apply(scene, 0.25);
        let label = g.maps.label();
        let kept = std::mem::take(&mut g.specs)
            .into_iter()
            .zip(std::mem::take(&mut g.methods))
            .filter(|(s, m)| match check(&under, m) {
                Ok(()) => true,
                Err(e) => {
                    refused.push((format!("{s} @ {label}"), e.to_string()));
                    false
                }
            });
        (g.specs, g.methods) = kept.unzip();
    }
    refused
}

/// The methods whose maps of the group's size go into arrays of the map budget
/// (`shadow_map_budget_mib`): one map over the budget fails them at their first frame, which is
/// known before the run. (The single-map methods allocate their one map outside the budget.)
pub fn one_map_over_budget(scene: &crate::scene::Scene, method: &Method) -> Result<()> {
    let r = &scene.render;
    let bytes = u64::from(r.shadow_map_size).pow(2) * 4;
    if r.maps != crate::scene::MapKind::Plain
        || !matches!(method.name(), "hard" | "regular" | "adaptive")
        || bytes <= u64::from(r.shadow_map_budget_mib) << 20
    {
        return Ok(());
    }
    let (size, budget) = (r.shadow_map_size, r.shadow_map_budget_mib);
    Err(Error::param(format!("one {size}x{size} shadow map ({} MiB) does not fit shadow_map_budget_mib = {budget} (raise it with --set to run them)", bytes >> 20)))
}

/// Local scope keeps all 289 lattice maps alive in at most two arrays of the map budget
/// (`shadow_map_budget_mib`, default 512 MiB): at 1024² and up they do not fit, and the adaptive
/// method refuses them, so those settings are left out (docs/frontier.md).
pub fn local_fits(size: u32, budget_mib: u32) -> bool {
    let per_array = (u64::from(budget_mib) << 20) / (u64::from(size) * u64::from(size) * 4);
    2 * per_array >= 289
}

/// The settings of one map configuration: method specs as written (a label may spell a preset
/// out) and the methods parsed from them.
/// `--budget T1,T2,…`: error-budget targets, each an RMSE of V in auto's range.
pub fn parse_budget(list: &[String]) -> Result<Vec<f32>> {
    let targets = list
        .iter()
        .map(|t| {
            t.trim()
                .parse::<f32>()
                .ok()
                .filter(|v| (0.0005..=0.5).contains(v))
                .ok_or_else(|| {
                    Error::param(format!(
                        "--budget `{t}`: a target RMSE of V in 0.0005..=0.5"
                    ))
                })
        })
        .collect::<Result<Vec<f32>>>()?;
    listed_once("--budget", list.iter().zip(targets.iter().copied()))?;
    Ok(targets)
}

#[derive(Clone, Debug)]
pub struct Group {
    pub maps: Maps,
    pub specs: Vec<String>,
    pub methods: Vec<Method>,
}

/// Settings the axes give, counted without building them (`--max-configs` is checked first):
/// per plain size every method spec, per hybrid configuration all but the two local adaptive
/// presets and the prefiltered maps.
pub fn count_of(axes: &Axes, budget_mib: u32) -> usize {
    let all = 2 * axes.n.len() + ADAPTIVE.len() + SINGLE_MAP.len();
    let prefiltered = SINGLE_MAP
        .iter()
        .filter(|s| Family::of_name(s) == Family::Filtered)
        .count();
    let local = ADAPTIVE
        .iter()
        .filter(|s| s.contains("scope=local"))
        .count();
    let plain: usize = axes
        .sizes
        .iter()
        .map(|&s| {
            if local_fits(s, budget_mib) {
                all
            } else {
                all - local
            }
        })
        .sum();
    plain.saturating_add(axes.hybrid.len().saturating_mul(all - prefiltered - local))
}

/// Settings in all groups.
pub fn count(groups: &[Group]) -> usize {
    groups.iter().map(|g| g.methods.len()).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_and_thin_grids() {
        let full = settings(&Axes::of(&Thinning::Full), 512).unwrap();
        // 32 regular grids + 4 adaptive + 8 single-map, at 4 sizes (no local adaptive at 1024² and
        // 2048² in 512 MiB); hybrid: all but local adaptive and the 5 prefiltered maps.
        assert_eq!(full.len(), 5);
        assert_eq!(full[0].methods.len(), 44);
        assert_eq!(full[2].methods.len(), 42);
        assert!(local_fits(512, 512) && !local_fits(1024, 512) && local_fits(1024, 1024));
        assert_eq!(full[4].methods.len(), 44 - 2 - 5);
        assert_eq!(full[4].specs.len(), full[4].methods.len());
        assert_eq!(count(&full), 4 * 44 - 4 + 37);
        let thin = settings(&Axes::of(&Thinning::Asked), 512).unwrap();
        assert_eq!(count(&thin), 2 * 28 - 2 + 21);
        for axes in [Axes::of(&Thinning::Full), Axes::of(&Thinning::Asked)] {
            for budget in [512, 4096] {
                assert_eq!(
                    count_of(&axes, budget),
                    count(&settings(&axes, budget).unwrap())
                );
            }
        }
        // --cull: every regular grid on plain maps culls, the hybrid group's do not.
        let axes = Axes {
            cull: true,
            ..Axes::of(&Thinning::Asked)
        };
        let culled = settings(&axes, 512).unwrap();
        assert_eq!(count(&culled), count(&thin));
        assert_eq!(
            culled[0]
                .specs
                .iter()
                .filter(|s| s.starts_with("regular:") && s.ends_with(",cull=on"))
                .count(),
            2 * THIN_N.len()
        );
        assert!(
            culled[0]
                .specs
                .contains(&"regular:n=5,layout=centred,cull=on".to_string())
                && culled[0]
                    .methods
                    .iter()
                    .zip(&culled[0].specs)
                    .all(|(m, s)| m.label() == *s || !s.starts_with("regular"))
        );
        assert!(
            culled[2]
                .specs
                .iter()
                .all(|s| !s.contains("cull=on") || s.starts_with("adaptive")),
            "hybrid: {:?}",
            culled[2].specs
        );
        assert!(
            Thinning::Asked.describe(&axes).ends_with(
                "hybrid maps [hybrid 2048→512]; the plain maps' regular grids culled (--cull)"
            ),
            "{}",
            Thinning::Asked.describe(&axes)
        );
        assert!(!Thinning::Asked
            .describe(&Axes::of(&Thinning::Asked))
            .contains("cull"));
        assert_eq!(
            Thinning::choose(false, false, 1_000_000).unwrap(),
            Thinning::Automatic(1_000_000)
        );
        assert_eq!(
            Thinning::choose(false, true, 1_000_000).unwrap(),
            Thinning::Full
        );
        assert!(Thinning::choose(true, true, 10).is_err());
    }

    #[test]
    fn settings_that_refuse_the_light_are_left_out_and_named() {
        let axes = Axes::of(&Thinning::Asked);
        let point = crate::scene::Scene::load("point-edge", &[]).unwrap();
        let mut groups = settings(&axes, 512).unwrap();
        let before = count(&groups);
        let refused = drop_refused(&mut groups, &point, |s, m| {
            m.check_light(s).map_err(Into::into)
        });
        // Local scope at 512² (1024² is already out by the map budget), the prefiltered maps at
        // both sizes, and the global presets under hybrid maps; the regular grids, hard, pcf and
        // pcss read a point light's cube maps of either kind.
        let names: Vec<&str> = refused.iter().map(|(s, _)| s.as_str()).collect();
        let mut want = vec![
            "adaptive:preset=seed,scope=local,cull=on @ plain 512".to_string(),
            "adaptive:preset=balanced,scope=local,cull=on @ plain 512".to_string(),
        ];
        for size in [512, 1024] {
            want.extend(
                ["esm", "vsm", "evsm", "msm", "csm"]
                    .iter()
                    .map(|m| format!("{m} @ plain {size}")),
            );
        }
        want.extend([
            "adaptive:preset=seed @ hybrid 2048→512".to_string(),
            "adaptive:preset=balanced @ hybrid 2048→512".to_string(),
        ]);
        assert_eq!(names, want);
        assert!(
            refused
                .iter()
                .all(|(_, why)| why.contains("light kind `point`") && why.contains("point-edge")),
            "{refused:?}"
        );
        assert!(
            refused[12].1.contains("cube maps need maps = plain"),
            "{}",
            refused[12].1
        );
        assert_eq!(count(&groups), before - 14);
        assert!(groups.iter().all(|g| g.specs.len() == g.methods.len()));
        assert!(
            groups[0].specs.iter().any(|s| s == "adaptive:preset=seed"),
            "global scope runs on a point light's plain maps"
        );
        let area = crate::scene::Scene::load("default", &[]).unwrap();
        let mut groups = settings(&axes, 512).unwrap();
        assert!(drop_refused(&mut groups, &area, |s, m| m
            .check_light(s)
            .map_err(Into::into))
        .is_empty());
        assert_eq!(count(&groups), before);
    }

    #[test]
    fn bad_axes() {
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        assert!(parse_n(&s(&["0"]))
            .unwrap_err()
            .to_string()
            .contains("--n `0`"));
        assert!(parse_n(&s(&["3", "3"]))
            .unwrap_err()
            .to_string()
            .contains("listed twice"));
        assert!(parse_sizes(&s(&["big"]))
            .unwrap_err()
            .to_string()
            .starts_with("--sizes: map configuration `big`"));
        assert!(parse_hybrid(&s(&["2048/3"]))
            .unwrap_err()
            .to_string()
            .starts_with("--hybrid: "));
        assert!(parse_hybrid(&s(&["none"])).unwrap().is_empty());
    }
}
