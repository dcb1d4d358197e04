//! `penumbra oracle` (docs/oracle.md): the most any per-region method could gain on a scene. Every
//! candidate of the menu (family.rs) renders the whole frame once, so each 8×8 tile's squared
//! error under each candidate is known exactly against the reference; the oracle gives each tile
//! one candidate so the frame meets T at the least price (solve.rs), paying each candidate's maps
//! once, each tile's pixel tests, nothing for the decision, and nothing for tiles the reference
//! shows uniformly lit or dark. Set against the cheapest single setting meeting T, that price
//! bounds what choosing per region could gain (`gain_bound`), with the grids alone and with the
//! whole family.

pub(crate) mod charts;
pub mod command;
pub mod family;
pub mod files;
pub mod solve;
pub mod tiles;

use crate::gpu::GpuContext;
use crate::record::judge::Judge;
use crate::record::measure;
use crate::record::RowCore;
use crate::reference::truth::{self, Cache};
use crate::reference::ReferenceMode;
use crate::scene::Scene;
use crate::studies::hybrid::Maps;
use crate::Result;
use family::{Candidate, Kind, Price};
use serde::Serialize;
use std::collections::BTreeMap;
use tiles::Tiles;

pub struct OracleJob {
    /// Each scene at each screen resolution asked for.
    pub scenes: Vec<Scene>,
    pub targets: Vec<f64>,
    pub menu: family::Menu,
    pub repeats: u32,
    pub reference: ReferenceMode,
    pub cache: Cache,
}

/// One candidate as measured on one scene and screen: `candidates.csv`.
#[derive(Clone, Debug, Serialize)]
pub struct CandidateLine {
    /// Scene, spec, method, params, maps, map size (the base of hybrid maps), RMSE, median frame
    /// time, adapter, build.
    #[serde(flatten)]
    pub core: RowCore,
    pub resolution: u32,
    /// Short name (`n=4@512`, `pcss@1024`, `n=4@h2048→512`, `balanced@512`).
    pub name: String,
    pub map_config: String,
    pub kind: Kind,
    /// Fastest and slowest timed frame, wall clock.
    pub frame_ms_min: f64,
    pub frame_ms_max: f64,
    /// Its price: the stages-mode frame's split scaled to the median.
    pub price: Price,
    pub stages_ms: BTreeMap<String, f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
}

/// A candidate the oracle chose for some tiles: a class of the split.
#[derive(Clone, Debug, Serialize)]
pub struct Class {
    pub candidate: String,
    pub kind: Kind,
    pub tiles: usize,
    /// The share of its tiles' geometry pixels in penumbra (0 < V < 1 in the reference).
    pub penumbra_share: f64,
}

/// The oracle on one scene, screen, target and menu: a row of `oracle.csv`.
#[derive(Clone, Debug, Serialize)]
pub struct OracleRow {
    pub scene: String,
    pub resolution: u32,
    pub target: f64,
    /// `grids` (the culled centred grids alone) or `family` (every candidate).
    pub menu: String,
    pub candidates: usize,
    /// The cheapest single setting of the menu whose RMSE is at most the target; its model time
    /// (fixed + maps + every pixel's tests) and its measured median.
    pub single: Option<String>,
    pub single_rmse: Option<f64>,
    pub single_model_ms: Option<f64>,
    pub single_measured_ms: Option<f64>,
    /// The oracle's frame (achievable) and the lower bound; none where no choice reaches T.
    pub oracle_ms: Option<f64>,
    pub oracle_rmse: Option<f64>,
    pub bound_ms: Option<f64>,
    /// single_model_ms / bound_ms: the most choosing per tile could gain.
    pub gain_bound: Option<f64>,
    /// The search closed (the bound is the optimum's); false: it stopped at its node limit and
    /// the bound is the least over the nodes left.
    pub closed: Option<bool>,
    /// single_model_ms / oracle_ms: what the oracle's own frame gains.
    pub gain_oracle: Option<f64>,
    /// Tiles with geometry, and of those uniformly lit or dark (free).
    pub tiles: usize,
    pub free_tiles: usize,
    /// The split: each candidate the oracle uses, most tiles first.
    pub split: Vec<Class>,
    /// The frame's RMSE with every tile at its own most accurate candidate: below it no choice goes.
    pub best_per_tile_rmse: f64,
    /// Signals a per-region method can read without the truth (docs/oracle.md): the share of
    /// geometry pixels in penumbra, and the single setting's pixel tests as a share of its frame,
    /// with what removing them all would gain, 1 / (1 − share).
    pub penumbra_share: f64,
    pub tests_share: Option<f64>,
    pub gain_tests_only: Option<f64>,
    /// Per tile in row order: the index of its class in `split`, −1 free, −2 no geometry.
    pub choice: Vec<i32>,
    pub tile_cols: u32,
    pub tile_rows: u32,
}

impl OracleRow {
    /// The classes that are not grids: where a one-map filter, hybrid maps or a preset enters.
    pub fn not_grids(&self) -> Vec<&Class> {
        self.split.iter().filter(|c| c.kind != Kind::Grid).collect()
    }
}

/// A measured candidate: its line and its squared error per tile.
struct Measured {
    line: CandidateLine,
    sse: Vec<f64>,
}

/// What one run of the study found.
pub struct OracleOutcome {
    pub candidates: Vec<CandidateLine>,
    pub rows: Vec<OracleRow>,
    /// Per scene and screen: the fixed stages' price every frame pays (median over candidates).
    pub fixed_ms: Vec<(String, u32, f64)>,
    pub adapter: String,
}

/// Every scene at every screen: measure the menu, then the oracle per target and menu.
pub fn run(ctx: &GpuContext, job: &OracleJob, log: &dyn Fn(&str)) -> Result<OracleOutcome> {
    let (groups, _) = family::groups(
        &job.menu,
        job.scenes
            .first()
            .map_or(512, |s| s.render.shadow_map_budget_mib),
    )?;
    let mut out = OracleOutcome {
        candidates: Vec::new(),
        rows: Vec::new(),
        fixed_ms: Vec::new(),
        adapter: format!("{} ({})", ctx.summary.name, ctx.summary.backend),
    };
    for scene in &job.scenes {
        let groups = usable(ctx, scene, &groups, log);
        let (measured, tiles, judge) = measure_scene(ctx, scene, &groups, job, log)?;
        let ok: Vec<&Measured> = measured
            .iter()
            .filter(|m| m.line.failed.is_none())
            .collect();
        let fixed = crate::record::stats::median(
            &ok.iter().map(|m| m.line.price.fixed_ms).collect::<Vec<_>>(),
        )
        .unwrap_or(0.0);
        out.fixed_ms
            .push((scene.name.clone(), scene.render.width, fixed));
        for menu in ["grids", "family"] {
            let cands: Vec<&Measured> = ok
                .iter()
                .copied()
                .filter(|m| menu == "family" || m.line.kind == Kind::Grid)
                .collect();
            for &target in &job.targets {
                let row = oracle_row(scene, menu, target, &cands, &tiles, &judge, fixed);
                log(&row_line(&row));
                out.rows.push(row);
            }
        }
        out.candidates.extend(measured.into_iter().map(|m| m.line));
    }
    Ok(out)
}

/// The groups with what the scene's light refuses, or the device cannot hold, left out (one
/// stderr line each).
fn usable(
    ctx: &GpuContext,
    scene: &Scene,
    groups: &[family::Group],
    log: &dyn Fn(&str),
) -> Vec<family::Group> {
    groups
        .iter()
        .map(|g| {
            let s = g.maps.apply(scene, 0.25);
            let candidates = g
                .candidates
                .iter()
                .filter(|c| {
                    match c
                        .method
                        .check_light(&s)
                        .map_err(|e| e.to_string())
                        .and_then(|_| {
                            crate::methods::sizes::check(ctx, &s, &c.method)
                                .map_err(|e| e.to_string())
                        }) {
                        Ok(()) => true,
                        Err(e) => {
                            log(&format!(
                                "{} left out on {} at {}²: {e}",
                                c.name(),
                                scene.name,
                                scene.render.width
                            ));
                            false
                        }
                    }
                })
                .cloned()
                .collect();
            family::Group {
                maps: g.maps,
                candidates,
            }
        })
        .filter(|g| !g.candidates.is_empty())
        .collect()
}

/// One scene and screen: the reference, its tiles, and every candidate measured (the measure
/// loop of compare, one run per map configuration) with its squared error per tile.
fn measure_scene(
    ctx: &GpuContext,
    scene: &Scene,
    groups: &[family::Group],
    job: &OracleJob,
    log: &dyn Fn(&str),
) -> Result<(Vec<Measured>, Tiles, Judge)> {
    let (g, reference) = truth::for_scene(ctx, scene, job.reference, &job.cache)?;
    let judge = Judge::new(scene, &g, reference.values.clone());
    log(&format!(
        "{} at {}²: {}",
        scene.name,
        scene.render.width,
        crate::studies::compare::reference_line(&reference, judge.geometry_pixels())
    ));
    let tiles = Tiles::of(&judge.reference, &judge.mask, judge.width, judge.height);
    let bar = crate::progress::bar(
        measure::frame_count(family::count(groups), job.repeats),
        "oracle",
    );
    let mut out = Vec::new();
    for group in groups {
        let s = group.maps.apply(scene, 0.25);
        let methods: Vec<crate::methods::Method> =
            group.candidates.iter().map(|c| c.method.clone()).collect();
        let mut on_frame =
            |m: &crate::methods::Method, phase: measure::Phase, _: &crate::frame::FrameResult| {
                bar.set_message(format!(
                    "{} {} {} {phase}",
                    scene.name,
                    group.maps.label(),
                    m.label()
                ));
                bar.inc(1);
            };
        let mut judge_frame =
            |i: usize, f: &crate::frame::FrameResult| -> Result<(f64, Vec<f64>)> {
                let rmse = judge.judge(&s, &methods[i].label(), f)?.metrics.rmse;
                Ok((rmse, tiles.sse(&f.visibility, &judge.reference)))
            };
        let measured = measure::measure(
            ctx,
            &s,
            &methods,
            job.repeats,
            &mut on_frame,
            &mut judge_frame,
        )?;
        let adapter =
            serde_json::Value::from(format!("{} ({})", ctx.summary.name, ctx.summary.backend));
        for (c, r) in group.candidates.iter().zip(measured) {
            let m = measured_line(scene, c, &adapter, r);
            crate::progress::suspend(|| match &m.line.failed {
                Some(why) => log(&crate::record::failed_line(&m.line.name, why)),
                None => log(&format!(
                    "{} {}²: {}: {} maps, median {:.1} ms, RMSE {:.4}",
                    scene.name,
                    scene.render.width,
                    m.line.name,
                    m.line.core.maps,
                    m.line.core.frame_ms,
                    m.line.core.rmse
                )),
            });
            out.push(m);
        }
    }
    bar.finish_and_clear();
    Ok((out, tiles, judge))
}

fn measured_line(
    scene: &Scene,
    c: &Candidate,
    adapter: &serde_json::Value,
    r: measure::Outcome<(f64, Vec<f64>)>,
) -> Measured {
    let map_size = match c.maps {
        Maps::Plain(size) => size,
        Maps::Hybrid { base, .. } => base,
    };
    let mut line = CandidateLine {
        core: RowCore {
            map_size,
            rmse: f64::NAN,
            frame_ms: f64::NAN,
            adapter: adapter.clone(),
            ..RowCore::of(&scene.name, &c.spec, &c.method)
        },
        resolution: scene.render.width,
        name: c.name(),
        map_config: c.maps.label(),
        kind: c.kind,
        frame_ms_min: f64::NAN,
        frame_ms_max: f64::NAN,
        price: Price::default(),
        stages_ms: BTreeMap::new(),
        failed: None,
    };
    match r {
        Ok(m) => {
            let t = &m.timing;
            (
                line.core.maps,
                line.core.rmse,
                line.core.frame_ms,
                line.frame_ms_min,
                line.frame_ms_max,
            ) = (t.shadow_maps, m.judged.0, t.median_ms, t.min_ms, t.max_ms);
            line.price = Price::of(&t.stages_ms, t.median_ms);
            line.stages_ms = t.stages_ms.clone();
            Measured {
                line,
                sse: m.judged.1,
            }
        }
        Err(why) => {
            line.failed = Some(why);
            Measured {
                line,
                sse: Vec::new(),
            }
        }
    }
}

/// The oracle of one menu at one target.
fn oracle_row(
    scene: &Scene,
    menu: &str,
    target: f64,
    cands: &[&Measured],
    tiles: &Tiles,
    judge: &Judge,
    fixed: f64,
) -> OracleRow {
    let n = judge.geometry_pixels() as f64;
    let model = |m: &Measured| fixed + m.line.price.maps_ms + m.line.price.tests_ms;
    let single = cands
        .iter()
        .filter(|m| m.line.core.rmse <= target)
        .min_by(|a, b| model(a).total_cmp(&model(b)));
    // The tiles that pay: geometry, not uniformly lit or dark.
    let paying: Vec<usize> = (0..tiles.px.len())
        .filter(|&t| tiles.px[t] > 0 && !tiles.free[t])
        .collect();
    let nk = cands.len();
    let mut p = solve::Problem {
        fixed_ms: fixed,
        maps_ms: cands.iter().map(|m| m.line.price.maps_ms).collect(),
        cost: Vec::new(),
        err: Vec::new(),
        budget: target * target * n,
    };
    for &t in &paying {
        for m in cands {
            p.cost
                .push(f64::from(tiles.px[t]) * m.line.price.tests_ms / n);
            p.err.push(m.sse[t]);
        }
    }
    let best_per_tile = if nk == 0 {
        f64::NAN
    } else {
        (p.least_err() / n).sqrt()
    };
    let solution = if nk == 0 { None } else { solve::solve(&p) };
    let geometry_tiles = tiles.px.iter().filter(|&&px| px > 0).count();
    let mut row = OracleRow {
        scene: scene.name.clone(),
        resolution: scene.render.width,
        target,
        menu: menu.to_string(),
        candidates: nk,
        single: single.map(|m| m.line.name.clone()),
        single_rmse: single.map(|m| m.line.core.rmse),
        single_model_ms: single.map(|m| model(m)),
        single_measured_ms: single.map(|m| m.line.core.frame_ms),
        oracle_ms: None,
        oracle_rmse: None,
        bound_ms: None,
        gain_bound: None,
        closed: None,
        gain_oracle: None,
        tiles: geometry_tiles,
        free_tiles: tiles.free.iter().filter(|&&f| f).count(),
        split: Vec::new(),
        best_per_tile_rmse: best_per_tile,
        penumbra_share: tiles.pen.iter().map(|&x| f64::from(x)).sum::<f64>() / n.max(1.0),
        tests_share: single.map(|m| m.line.price.tests_ms / model(m)),
        gain_tests_only: single.map(|m| model(m) / (model(m) - m.line.price.tests_ms)),
        choice: tiles
            .px
            .iter()
            .zip(&tiles.free)
            .map(|(&px, &free)| {
                if px == 0 {
                    -2
                } else if free {
                    -1
                } else {
                    -3
                }
            })
            .collect(),
        tile_cols: tiles.cols,
        tile_rows: tiles.rows,
    };
    let Some(s) = solution else {
        row.choice
            .iter_mut()
            .filter(|c| **c == -3)
            .for_each(|c| *c = -2);
        return row;
    };
    row.oracle_ms = Some(s.frame_ms);
    row.oracle_rmse = Some((s.err / n).sqrt());
    row.bound_ms = Some(s.bound_ms);
    row.closed = Some(s.closed);
    row.gain_bound = row.single_model_ms.map(|m| m / s.bound_ms);
    row.gain_oracle = row.single_model_ms.map(|m| m / s.frame_ms);
    // The classes, most tiles first; each tile's index into them.
    let mut used: Vec<(usize, usize)> = (0..nk)
        .map(|k| (k, s.choice.iter().filter(|&&c| c == k).count()))
        .filter(|(_, c)| *c > 0)
        .collect();
    used.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    for (i, &t) in paying.iter().enumerate() {
        row.choice[t] = used
            .iter()
            .position(|(k, _)| *k == s.choice[i])
            .expect("a chosen candidate is used") as i32;
    }
    row.split = used
        .iter()
        .map(|&(k, count)| {
            let mine: Vec<usize> = paying
                .iter()
                .zip(&s.choice)
                .filter(|(_, &c)| c == k)
                .map(|(&t, _)| t)
                .collect();
            let (pen, px) = mine.iter().fold((0u64, 0u64), |(a, b), &t| {
                (a + u64::from(tiles.pen[t]), b + u64::from(tiles.px[t]))
            });
            Class {
                candidate: cands[k].line.name.clone(),
                kind: cands[k].line.kind,
                tiles: count,
                penumbra_share: pen as f64 / px.max(1) as f64,
            }
        })
        .collect();
    row
}

/// One stderr line per row.
fn row_line(r: &OracleRow) -> String {
    let f = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.1}"));
    let g = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.2}×"));
    format!(
        "{} {}² T = {} {}: single {} ({} ms), oracle {} ms, bound {} ms, gain_bound {}",
        r.scene,
        r.resolution,
        r.target,
        r.menu,
        r.single.as_deref().unwrap_or("none"),
        f(r.single_model_ms),
        f(r.oracle_ms),
        f(r.bound_ms),
        g(r.gain_bound)
    )
}
