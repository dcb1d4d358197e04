//! `penumbra certify-promise`: `auto:target=T` against its oracle on the rows of committed
//! frontiers (docs/certify.md §6). Each frontier's `auto` line names its oracle, the cheapest fixed
//! setting whose measured RMSE is at most T; the fixed settings render the same V on this build,
//! so the oracle stands, and only `auto` is rendered again: beside its oracle in one `compare`
//! window under the oracle's map size (their frames interleaved, so both see the same load), or
//! alone at 512² where no fixed setting reaches T. The counts are the promise's.

use crate::record::row_core::read_csv;
use crate::record::{Provenance, RowCore};
use crate::reference::truth::Cache;
use crate::scene::Scene;
use crate::studies::calibration::half;
use crate::studies::compare::{self, CompareJob};
use crate::studies::frontier::budget::{MET_SHARE, TIME_RATIO, TIME_SHARE};
use crate::studies::frontier::FrontierLine;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One row: `auto:target=T` on a scene, beside its oracle where one reaches T.
///
/// Its serde reads the study's own columns of `promise.csv`; [`parse_csv`] reads the core from
/// the core's columns (see [`crate::record::row_core::read_csv`]).
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct PromiseRow {
    /// auto's row as `compare` measured it: scene, spec (`auto:target=T`), its maps and the map
    /// size it rendered, the RMSE, the median frame time of the timed frames (the chosen
    /// setting alone, after the deciding frame; `ms` in files written before), adapter, build
    /// and T (always there: [`parse_csv`] refuses a row without it).
    #[serde(skip)]
    pub core: RowCore,
    pub half: String,
    /// What auto rendered: `regular:n=5,layout=centred @ 1024` or a filter's label.
    pub choice: String,
    pub target_met: bool,
    /// The chosen candidate's certified bound (the least tested where out of reach), its kind.
    pub bound: f64,
    pub bound_kind: String,
    /// The frame that chose: the estimate's tries and the certified decision, ms; candidates tested.
    pub decision_ms: f64,
    pub tests: usize,
    /// The oracle (`spec @ map_config`), its maps, its RMSE rendered again and in the frontier, its ms.
    pub oracle: Option<String>,
    pub oracle_maps: Option<u32>,
    pub oracle_rmse: Option<f64>,
    pub frontier_oracle_rmse: Option<f64>,
    pub oracle_ms: Option<f64>,
    pub time_over_oracle: Option<f64>,
}

impl PromiseRow {
    /// The study's own columns, after the core's.
    pub const OWN: [&'static str; 13] = [
        "half",
        "choice",
        "target_met",
        "bound",
        "bound_kind",
        "decision_ms",
        "tests",
        "oracle",
        "oracle_maps",
        "oracle_rmse",
        "frontier_oracle_rmse",
        "oracle_ms",
        "time_over_oracle",
    ];

    /// T, the target auto was asked for.
    pub fn target(&self) -> f64 {
        self.core.target.unwrap_or(f64::NAN)
    }
}

/// The auto rows of one frontier (its `frontier.jsonl` lines).
fn budget_rows(lines: &[FrontierLine]) -> Vec<&FrontierLine> {
    lines
        .iter()
        .filter(|l| l.is_budget() && l.core.spec.starts_with("auto:"))
        .collect()
}

/// Reads `dir/frontier.jsonl`.
pub fn read_frontier(dir: &Path) -> Result<Vec<FrontierLine>> {
    let path = dir.join("frontier.jsonl");
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            serde_json::from_str(l).map_err(|e| Error::param(format!("{}: {e}", path.display())))
        })
        .collect()
}

/// Retakes every auto row of the frontier in `dir`.
pub fn run_frontier(
    ctx: &crate::gpu::GpuContext,
    dir: &Path,
    repeats: u32,
    log: &dyn Fn(&str),
) -> Result<Vec<PromiseRow>> {
    let lines = read_frontier(dir)?;
    let mut rows = Vec::new();
    for b in budget_rows(&lines) {
        let target = b.target().ok_or_else(|| {
            Error::param(format!(
                "{}: `{}` has no target",
                dir.display(),
                b.core.spec
            ))
        })?;
        let oracle = b.oracle.as_ref().and_then(|o| {
            lines
                .iter()
                .find(|l| !l.is_budget() && l.failed.is_none() && &l.setting() == o)
        });
        let size = oracle.map_or(512, |o| o.core.map_size);
        let mut sets = vec![
            ("resolution".to_string(), b.resolution[0].to_string()),
            ("shadow_map_size".to_string(), size.to_string()),
        ];
        if b.resolution[0] != b.resolution[1] {
            sets[0] = ("width".into(), b.resolution[0].to_string());
            sets.push(("height".into(), b.resolution[1].to_string()));
        }
        let scene = Scene::load(&b.core.scene, &sets)?;
        let mut specs = vec![format!("auto:target={target}")];
        if let Some(o) = oracle {
            specs.push(o.core.spec.clone());
        }
        let methods = specs
            .iter()
            .map(|s| crate::methods::Method::parse(s, &[]).map_err(Error::from))
            .collect::<Result<Vec<_>>>()?;
        let provenance =
            vec![Provenance::of_scene("certify-promise", &scene, &[], None); methods.len()];
        let job = CompareJob {
            scene: &scene,
            methods,
            repeats: if oracle.is_some() { repeats } else { 1 },
            reference: crate::reference::ReferenceMode::DEFAULT_CONTINUOUS,
            cache: Cache::default_for(false),
            provenance,
            pictures: false,
            certify: None,
        };
        let outcome = compare::run(ctx, &job, &|_| {})?;
        let a = &outcome.rows[0];
        if let Some(why) = &a.failed {
            return Err(Error::param(format!(
                "{} at {target}: auto failed: {why}",
                b.core.scene
            )));
        }
        let record = outcome
            .files
            .iter()
            .find(|(name, _)| name.starts_with("images/auto") && name.ends_with("/run.json"))
            .and_then(|(_, bytes)| serde_json::from_slice::<serde_json::Value>(bytes).ok())
            .and_then(|r| crate::methods::auto::AutoRecord::read(&r["method_record"]))
            .ok_or_else(|| {
                Error::param(format!("{} at {target}: no run.json of auto", b.core.scene))
            })?;
        let o = outcome.rows.get(1).filter(|r| r.failed.is_none());
        let choice = match &record.renders {
            Some(filter) => filter.clone(),
            None => format!("{} @ {}", record.chosen.spec, record.chosen.map_size),
        };
        let row = PromiseRow {
            core: RowCore {
                scene: b.core.scene.clone(),
                // auto renders its grid at the size it chose, a one-map filter at the scene's.
                map_size: match record.renders {
                    Some(_) => a.core.map_size,
                    None => record.chosen.map_size,
                },
                target: Some(target),
                ..a.core.clone()
            },
            half: half(&b.core.scene).name().to_string(),
            choice,
            target_met: record.target_met,
            bound: record.reported(),
            bound_kind: record
                .certified
                .as_ref()
                .map_or("estimate", |c| c.bound_kind.name())
                .to_string(),
            decision_ms: record.decision_ms(),
            tests: record.certified.as_ref().map_or(0, |c| c.tests.len()),
            oracle: oracle.map(FrontierLine::setting),
            oracle_maps: o.map(|o| o.core.maps),
            oracle_rmse: o.map(|o| o.metrics.rmse),
            frontier_oracle_rmse: oracle.map(|o| o.core.rmse),
            oracle_ms: o.map(|o| o.core.frame_ms),
            time_over_oracle: o.map(|o| a.core.frame_ms / o.core.frame_ms),
        };
        log(&format!(
            "{} at {target}: {} ({} maps), RMSE {:.5} ({:.2} T), {} bound {:.5}{}",
            row.core.scene,
            row.choice,
            row.core.maps,
            row.core.rmse,
            row.core.rmse / target,
            if row.target_met {
                "met,"
            } else {
                "not met, least"
            },
            row.bound,
            row.time_over_oracle.map_or(String::new(), |r| format!(
                ", {r:.2} × the oracle ({})",
                row.oracle.as_deref().unwrap_or("")
            ))
        ));
        rows.push(row);
    }
    Ok(rows)
}

/// The counts against the promise.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Counts {
    pub rows: usize,
    pub under: usize,
    /// Rows some fixed setting reaches (an oracle), and those of them under T.
    pub reachable: usize,
    pub reachable_under: usize,
    pub false_met: usize,
    pub not_met: usize,
    /// Rows with an oracle timed beside it, those within TIME_RATIO, the median ratio.
    pub timed: usize,
    pub quick: usize,
    pub median_ratio: f64,
    pub median_decision_ms: f64,
}

pub fn counts(rows: &[PromiseRow]) -> Counts {
    let reach: Vec<&PromiseRow> = rows.iter().filter(|r| r.oracle.is_some()).collect();
    let ratios: Vec<f64> = reach.iter().filter_map(|r| r.time_over_oracle).collect();
    let decisions: Vec<f64> = rows.iter().map(|r| r.decision_ms).collect();
    Counts {
        rows: rows.len(),
        under: rows.iter().filter(|r| r.core.rmse <= r.target()).count(),
        reachable: reach.len(),
        reachable_under: reach.iter().filter(|r| r.core.rmse <= r.target()).count(),
        false_met: rows
            .iter()
            .filter(|r| r.target_met && r.core.rmse > r.target())
            .count(),
        not_met: rows.iter().filter(|r| !r.target_met).count(),
        timed: ratios.len(),
        quick: ratios.iter().filter(|&&r| r <= TIME_RATIO).count(),
        median_ratio: crate::record::stats::median(&ratios).unwrap_or(f64::NAN),
        median_decision_ms: crate::record::stats::median(&decisions).unwrap_or(f64::NAN),
    }
}

fn share(a: usize, b: usize) -> String {
    format!("{a} of {b} ({:.0}%)", 100.0 * a as f64 / b.max(1) as f64)
}

/// The counts and the rows as Markdown.
pub fn markdown(rows: &[PromiseRow]) -> String {
    let c = counts(rows);
    let mut s = format!(
        "| count | rows | the promise |\n|---|---|---:|\n\
         | measured RMSE ≤ T, all rows | {} | {:.0}% |\n\
         | measured RMSE ≤ T, rows some fixed setting reaches | {} | {:.0}% |\n\
         | reported met while measured over T | {} | 0 |\n\
         | reported not met (naming the least bound) | {} | every unreachable row |\n\
         | time ≤ {TIME_RATIO} × the oracle's, side by side | {}, median {:.2} | {:.0}% |\n\
         | the decision's cost (the estimate's tries and the certified decision), median | {:.0} ms | reported apart |\n\n",
        share(c.under, c.rows),
        MET_SHARE * 100.0,
        share(c.reachable_under, c.reachable),
        MET_SHARE * 100.0,
        c.false_met,
        c.not_met,
        share(c.quick, c.timed),
        c.median_ratio,
        TIME_SHARE * 100.0,
        c.median_decision_ms,
    );
    s += "| scene | half | T | choice | maps | RMSE/T | reported | decision ms | oracle | time/oracle |\n|---|---|---:|---|---:|---:|---|---:|---|---:|\n";
    for r in rows {
        let reported = if r.target_met {
            format!("met (bound {:.5})", r.bound)
        } else {
            format!("not met: least bound {:.5}", r.bound)
        };
        s += &format!(
            "| {} | {} | {} | {} | {} | {:.2} | {reported} | {:.0} | {} | {} |\n",
            r.core.scene,
            r.half,
            r.target(),
            r.choice,
            r.core.maps,
            r.core.rmse / r.target(),
            r.decision_ms,
            r.oracle.as_deref().unwrap_or("none reaches it"),
            r.time_over_oracle.map_or("-".into(), |t| format!("{t:.2}"))
        );
    }
    s
}

/// The rows as CSV: the core's columns, then the study's own.
pub fn csv(rows: &[PromiseRow]) -> String {
    let opt = |v: Option<f64>| v.map_or(String::new(), |x| x.to_string());
    let cells = rows.iter().map(|r| {
        let mut c = r.core.cells();
        c.extend([
            r.half.clone(),
            r.choice.clone(),
            r.target_met.to_string(),
            r.bound.to_string(),
            r.bound_kind.clone(),
            r.decision_ms.to_string(),
            r.tests.to_string(),
            r.oracle.clone().unwrap_or_default(),
            r.oracle_maps.map_or(String::new(), |m| m.to_string()),
            opt(r.oracle_rmse),
            opt(r.frontier_oracle_rmse),
            opt(r.oracle_ms),
            opt(r.time_over_oracle),
        ]);
        c
    });
    crate::record::csv::lines(std::iter::once(RowCore::csv_header(&PromiseRow::OWN)).chain(cells))
}

/// Rows from the CSV [`csv`] writes (empty cells: none). Files written before the core
/// (results/certify-promise) call the frame time `ms`.
pub fn parse_csv(text: &str) -> Result<Vec<PromiseRow>> {
    let rows = read_csv::<PromiseRow>(text, &[("frame_ms", "ms")])
        .map_err(|e| Error::param(format!("promise rows: {e}")))?;
    rows.into_iter()
        .enumerate()
        .map(|(i, (core, row))| match core.target {
            Some(_) => Ok(PromiseRow { core, ..row }),
            None => Err(Error::param(format!(
                "promise rows: row {}: no target",
                i + 1
            ))),
        })
        .collect()
}

/// Truth-free checks the command makes before the GPU starts: each folder holds a frontier with
/// auto rows, on a scene lit by an area light.
pub fn check(dir: &Path) -> Result<usize> {
    let lines = read_frontier(dir)?;
    let rows = budget_rows(&lines);
    if rows.is_empty() {
        return Err(Error::param(format!(
            "{}: its frontier.jsonl has no auto:target=T row (run `penumbra frontier --budget T`)",
            dir.display()
        )));
    }
    Ok(rows.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(target: f64, rmse: f64, met: bool, ratio: Option<f64>) -> PromiseRow {
        PromiseRow {
            core: RowCore {
                scene: "s".into(),
                spec: format!("auto:target={target}"),
                method: "auto".into(),
                maps: 1,
                rmse,
                frame_ms: 2.0,
                target: Some(target),
                ..RowCore::default()
            },
            half: "fitting".into(),
            choice: "pcss".into(),
            target_met: met,
            bound: rmse * 1.1,
            bound_kind: "calibrated".into(),
            decision_ms: 100.0,
            tests: 1,
            oracle: ratio.map(|_| "pcss @ plain 512".into()),
            oracle_maps: ratio.map(|_| 1),
            oracle_rmse: ratio.map(|_| rmse),
            frontier_oracle_rmse: ratio.map(|_| rmse),
            oracle_ms: ratio.map(|r| 2.0 / r),
            time_over_oracle: ratio,
        }
    }

    #[test]
    fn the_counts_read_each_promise() {
        let rows = vec![
            row(0.02, 0.015, true, Some(1.0)),
            row(0.02, 0.021, true, Some(1.5)),
            row(0.012, 0.02, false, None),
            row(0.03, 0.01, true, Some(1.2)),
        ];
        let c = counts(&rows);
        assert_eq!(
            (
                c.rows,
                c.under,
                c.reachable,
                c.reachable_under,
                c.false_met,
                c.not_met,
                c.timed,
                c.quick
            ),
            (4, 2, 3, 2, 1, 1, 3, 2)
        );
        assert_eq!(c.median_ratio, 1.2);
        let md = markdown(&rows);
        assert!(
            md.contains("| measured RMSE ≤ T, all rows | 2 of 4 (50%) | 95% |"),
            "{md}"
        );
        assert!(
            md.contains(
                "| time ≤ 1.3 × the oracle's, side by side | 2 of 3 (67%), median 1.20 | 90% |"
            ),
            "{md}"
        );
        assert_eq!(parse_csv(&csv(&rows)).unwrap(), rows);
        let mut untargeted = rows[1].clone();
        untargeted.core.target = None;
        assert_eq!(
            parse_csv(&csv(&[rows[0].clone(), untargeted]))
                .unwrap_err()
                .to_string(),
            "promise rows: row 2: no target"
        );
    }

    /// The committed rows (written before the core: `ms` for the frame time, no spec) read, and
    /// give the committed counts and table, byte for byte.
    #[test]
    fn the_committed_rows_read_and_give_the_committed_table() {
        let dir =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../results/certify-promise");
        let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
        let rows = parse_csv(&read("promise.csv")).unwrap();
        assert_eq!(rows.len(), 45);
        let first = &rows[0];
        assert_eq!(
            (
                first.core.scene.as_str(),
                first.target(),
                first.core.maps,
                first.core.frame_ms
            ),
            ("analytic-square", 0.03, 1, 4.136334000000001)
        );
        assert_eq!(markdown(&rows), read("promise.md"));
        assert_eq!(parse_csv(&csv(&rows)).unwrap(), rows);
    }
}
