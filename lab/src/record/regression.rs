//! `penumbra check --baseline OLD/results.jsonl NEW/results.jsonl --max time=+10%,rmse=+2%`:
//! rows matched by scene, method and parameters; a table of deltas; a regression is any metric
//! worse than its tolerance, or a baseline row with no match. Timing counts only when both rows
//! were measured on the same adapter.

use crate::record::row::ResultRow;
use crate::{Error, Result};
use std::fmt::Write;

/// Which way a metric gets worse.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Worse {
    Up,
    Down,
}

struct MetricDef {
    name: &'static str,
    worse: Worse,
    timing: bool,
    value: fn(&ResultRow) -> Option<f64>,
}

const METRICS: &[MetricDef] = &[
    MetricDef {
        name: "time",
        worse: Worse::Up,
        timing: true,
        value: |r| Some(r.core.frame_ms),
    },
    MetricDef {
        name: "maps",
        worse: Worse::Up,
        timing: false,
        value: |r| Some(f64::from(r.core.maps)),
    },
    MetricDef {
        name: "syncs",
        worse: Worse::Up,
        timing: false,
        value: |r| Some(f64::from(r.syncs)),
    },
    MetricDef {
        name: "rmse",
        worse: Worse::Up,
        timing: false,
        value: |r| Some(r.metrics.rmse),
    },
    MetricDef {
        name: "mae",
        worse: Worse::Up,
        timing: false,
        value: |r| Some(r.metrics.mae),
    },
    MetricDef {
        name: "max_abs",
        worse: Worse::Up,
        timing: false,
        value: |r| Some(r.metrics.max_abs),
    },
    // Infinite PSNR (identical images) is stored as null.
    MetricDef {
        name: "psnr",
        worse: Worse::Down,
        timing: false,
        value: |r| Some(r.metrics.psnr.unwrap_or(f64::INFINITY)),
    },
    MetricDef {
        name: "ssim",
        worse: Worse::Down,
        timing: false,
        value: |r| Some(r.metrics.ssim),
    },
    MetricDef {
        name: "flip",
        worse: Worse::Up,
        timing: false,
        value: |r| Some(r.metrics.flip_mean),
    },
    MetricDef {
        name: "flip_p95",
        worse: Worse::Up,
        timing: false,
        value: |r| Some(r.metrics.flip_p95),
    },
    MetricDef {
        name: "flip_p99",
        worse: Worse::Up,
        timing: false,
        value: |r| Some(r.metrics.flip_p99),
    },
    MetricDef {
        name: "penumbra_rmse",
        worse: Worse::Up,
        timing: false,
        value: |r| r.metrics.penumbra_rmse,
    },
    MetricDef {
        name: "bad",
        worse: Worse::Up,
        timing: false,
        value: |r| Some(r.metrics.bad_pixel_share),
    },
];

/// The tolerances used when `--max` is not given.
pub const DEFAULT_MAX: &str = "time=+10%,maps=+0,rmse=+2%,flip=+2%";

/// How much one metric may get worse: a share of the baseline (`+10%`) or an amount (`+0.001`).
#[derive(Clone, Debug, PartialEq)]
pub struct Tolerance {
    pub metric: &'static str,
    pub amount: f64,
    pub relative: bool,
}

impl Tolerance {
    fn def(&self) -> &'static MetricDef {
        METRICS
            .iter()
            .find(|m| m.name == self.metric)
            .expect("parsed from METRICS")
    }

    /// The worst value `new` may take given `old`.
    fn limit(&self, old: f64) -> f64 {
        let by = if self.relative {
            old.abs() * self.amount
        } else {
            self.amount
        };
        match self.def().worse {
            Worse::Up => old + by,
            Worse::Down => old - by,
        }
    }

    fn text(&self) -> String {
        let sign = if self.def().worse == Worse::Up {
            '+'
        } else {
            '-'
        };
        if self.relative {
            format!("{sign}{}%", self.amount * 100.0)
        } else {
            format!("{sign}{}", self.amount)
        }
    }
}

/// `time=+10%,rmse=+2%,maps=+0,psnr=-0.5`: a sign, if given, must point the way the metric gets
/// worse (up for times and errors, down for PSNR and SSIM).
pub fn parse_max(text: &str) -> Result<Vec<Tolerance>> {
    let names = || {
        METRICS
            .iter()
            .map(|m| m.name)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut out: Vec<Tolerance> = Vec::new();
    for item in text.split(',').map(str::trim) {
        let bad = |why: String| Error::param(format!("--max `{item}`: {why}"));
        let (key, value) = item.split_once('=').ok_or_else(|| {
            bad("expected METRIC=+AMOUNT or METRIC=+PERCENT%, e.g. time=+10%".into())
        })?;
        let def = METRICS
            .iter()
            .find(|m| m.name == key.trim())
            .ok_or_else(|| {
                bad(format!(
                    "unknown metric `{}` (known: {})",
                    key.trim(),
                    names()
                ))
            })?;
        let mut v = value.trim();
        // One `%` at most: `+2%%` is a typo, not a percentage.
        let relative = v.ends_with('%');
        v = v.strip_suffix('%').unwrap_or(v);
        let wrong = match def.worse {
            Worse::Up => v.starts_with('-'),
            Worse::Down => v.starts_with('+'),
        };
        if wrong {
            let sign = if def.worse == Worse::Up { "+" } else { "-" };
            return Err(bad(format!(
                "{} gets worse {}; write {}={sign}{}",
                def.name,
                if def.worse == Worse::Up {
                    "upwards"
                } else {
                    "downwards"
                },
                def.name,
                &value.trim()[1..]
            )));
        }
        let number: f64 = v
            .trim_start_matches(['+', '-'])
            .parse()
            .map_err(|_| bad(format!("`{}` is not a number", value.trim())))?;
        if !number.is_finite() || number < 0.0 {
            return Err(bad(format!("`{}` is not a finite amount", value.trim())));
        }
        if out.iter().any(|t| t.metric == def.name) {
            return Err(bad(format!("{} is given twice", def.name)));
        }
        out.push(Tolerance {
            metric: def.name,
            amount: if relative { number / 100.0 } else { number },
            relative,
        });
    }
    Ok(out)
}

/// The key rows are matched by.
pub fn row_key(r: &ResultRow) -> String {
    format!("{}|{}|{}", r.core.scene, r.core.method, r.core.params)
}

fn adapter_name(r: &ResultRow) -> String {
    let a = &r.core.adapter;
    let s = |k: &str| a.get(k).and_then(|v| v.as_str()).unwrap_or("").to_string();
    if a.is_object() {
        format!(
            "{} ({}, {} {})",
            s("name"),
            s("backend"),
            s("driver"),
            s("driver_info")
        )
        .replace(" )", ")")
    } else {
        a.to_string()
    }
}

/// One compared figure.
#[derive(Clone, Debug)]
pub struct Delta {
    pub label: String,
    pub scene: String,
    pub metric: &'static str,
    pub old: f64,
    pub new: f64,
    pub limit: String,
    /// `ok`, `REGRESSION`, or why it was not judged.
    pub verdict: String,
    pub regression: bool,
}

pub struct Outcome {
    pub deltas: Vec<Delta>,
    /// Lines said below the table: adapters, unmatched rows.
    pub notes: Vec<String>,
    pub regressions: usize,
    pub matched: usize,
}

/// Compares `new` with `baseline` under `max`.
pub fn check(baseline: &[ResultRow], new: &[ResultRow], max: &[Tolerance]) -> Outcome {
    let mut deltas = Vec::new();
    let mut notes = Vec::new();
    let mut regressions = 0;
    let mut matched = 0;
    let mut timing_note = None;
    for old in baseline {
        let Some(cur) = new.iter().find(|r| row_key(r) == row_key(old)) else {
            notes.push(format!(
                "REGRESSION: `{}` on {} is in the baseline but not in the new results",
                old.label(),
                old.core.scene
            ));
            regressions += 1;
            continue;
        };
        matched += 1;
        // A failed setting has no figures: failing now is a regression, having failed before is not compared.
        if let Some(reason) = &cur.failed {
            notes.push(format!(
                "REGRESSION: `{}` on {} failed: {reason}",
                old.label(),
                old.core.scene
            ));
            regressions += 1;
            continue;
        }
        if let Some(reason) = &old.failed {
            notes.push(format!(
                "not compared: `{}` on {} failed in the baseline ({reason})",
                old.label(),
                old.core.scene
            ));
            continue;
        }
        if old.resolution != cur.resolution || old.reference != cur.reference {
            let size = |r: Option<[u32; 2]>| {
                r.map_or("an unknown size".to_string(), |[w, h]| format!("{w}x{h}"))
            };
            notes.push(format!(
                "REGRESSION: `{}` on {} was measured differently ({} against {}, now {} against {}): not comparable",
                old.label(), old.core.scene, size(old.resolution), old.reference, size(cur.resolution), cur.reference
            ));
            regressions += 1;
            continue;
        }
        let same_adapter = old.core.adapter == cur.core.adapter;
        for t in max {
            let def = t.def();
            let (Some(a), Some(b)) = ((def.value)(old), (def.value)(cur)) else {
                continue;
            };
            let mut d = Delta {
                label: old.label(),
                scene: old.core.scene.clone(),
                metric: def.name,
                old: a,
                new: b,
                limit: t.text(),
                verdict: "ok".into(),
                regression: false,
            };
            if def.timing && !same_adapter {
                d.verdict = "not judged: adapters differ".into();
                timing_note.get_or_insert_with(|| {
                    format!(
                        "timing not compared: the adapters differ (baseline {}, new {})",
                        adapter_name(old),
                        adapter_name(cur)
                    )
                });
            } else {
                let limit = t.limit(a);
                let worse = match def.worse {
                    Worse::Up => b > limit,
                    Worse::Down => b < limit,
                };
                if worse {
                    d.verdict = "REGRESSION".into();
                    d.regression = true;
                    regressions += 1;
                }
            }
            deltas.push(d);
        }
    }
    for cur in new
        .iter()
        .filter(|r| !baseline.iter().any(|o| row_key(o) == row_key(r)))
    {
        notes.push(format!(
            "new: `{}` on {} has no baseline row",
            cur.label(),
            cur.core.scene
        ));
    }
    notes.extend(timing_note);
    Outcome {
        deltas,
        notes,
        regressions,
        matched,
    }
}

fn num(v: f64) -> String {
    if v.is_infinite() {
        "inf".into()
    } else if v != 0.0 && v.abs() < 1e-3 {
        format!("{v:.3e}")
    } else if v.fract() == 0.0 && v.abs() < 1e9 {
        format!("{v:.0}")
    } else {
        format!("{v:.4}")
    }
}

/// `+12.3%` (or the difference when the baseline is 0).
pub fn change(old: f64, new: f64) -> String {
    if old == new {
        "0".into()
    } else if old != 0.0 && old.is_finite() && new.is_finite() {
        format!("{:+.2}%", 100.0 * (new - old) / old.abs())
    } else {
        format!("{:+}", num(new - old))
    }
}

/// The table `check` prints.
pub fn render(o: &Outcome) -> String {
    let width = o
        .deltas
        .iter()
        .map(|d| d.label.chars().count() + d.scene.chars().count() + 3)
        .max()
        .unwrap_or(10)
        .max(10);
    let mut out = format!(
        "{:width$}  {:>13} {:>12} {:>12} {:>10} {:>8}  verdict\n",
        "row", "metric", "baseline", "new", "change", "max"
    );
    for d in &o.deltas {
        let _ = writeln!(
            out,
            "{:width$}  {:>13} {:>12} {:>12} {:>10} {:>8}  {}",
            format!("{} ({})", d.label, d.scene),
            d.metric,
            num(d.old),
            num(d.new),
            change(d.old, d.new),
            d.limit,
            d.verdict
        );
    }
    for n in &o.notes {
        let _ = writeln!(out, "{n}");
    }
    let _ = writeln!(
        out,
        "{} rows matched, {} regressions",
        o.matched, o.regressions
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(label: &str, ms: f64, maps: u32, rmse: f64) -> ResultRow {
        let mut r = ResultRow {
            core: crate::record::RowCore {
                scene: "s".into(),
                method: "regular".into(),
                params: serde_json::json!({ "n": label }),
                frame_ms: ms,
                maps,
                rmse,
                ..Default::default()
            },
            ..Default::default()
        };
        r.metrics.rmse = rmse;
        r.metrics.psnr = Some(30.0);
        r
    }

    #[test]
    fn tolerances_parse_and_bad_ones_are_one_line_errors() {
        let t = parse_max("time=+10%,maps=+0,rmse=0.001,psnr=-0.5").unwrap();
        assert_eq!(
            t[0],
            Tolerance {
                metric: "time",
                amount: 0.1,
                relative: true
            }
        );
        assert_eq!(
            t[1],
            Tolerance {
                metric: "maps",
                amount: 0.0,
                relative: false
            }
        );
        assert_eq!(
            t[2],
            Tolerance {
                metric: "rmse",
                amount: 0.001,
                relative: false
            }
        );
        assert_eq!(t[3].limit(30.0), 29.5);
        for (bad, msg) in [
            ("time", "--max `time`: expected METRIC=+AMOUNT"),
            (
                "speed=+1%",
                "--max `speed=+1%`: unknown metric `speed` (known: time, maps,",
            ),
            (
                "time=-10%",
                "--max `time=-10%`: time gets worse upwards; write time=+10%",
            ),
            (
                "psnr=+1",
                "--max `psnr=+1`: psnr gets worse downwards; write psnr=-1",
            ),
            ("rmse=+x%", "--max `rmse=+x%`: `+x%` is not a number"),
            ("maps=+0,maps=+1", "--max `maps=+1`: maps is given twice"),
        ] {
            let e = parse_max(bad).unwrap_err().to_string();
            assert!(e.starts_with(msg), "{bad}: {e}");
        }
    }

    #[test]
    fn a_setting_that_fails_now_is_a_regression_and_one_that_failed_before_is_not_compared() {
        let max = parse_max(DEFAULT_MAX).unwrap();
        let base = vec![row("a", 100.0, 10, 0.010), row("b", 50.0, 4, 0.020)];
        let mut now = base.clone();
        now[0] = ResultRow {
            failed: Some("overflow: x".into()),
            ..row("a", 0.0, 0, 0.0)
        };
        let o = check(&base, &now, &max);
        assert_eq!((o.regressions, o.matched), (1, 2), "{}", render(&o));
        assert!(
            o.notes
                .contains(&"REGRESSION: `regular(n=a)` on s failed: overflow: x".to_string()),
            "{:?}",
            o.notes
        );
        let o = check(&now, &base, &max);
        assert_eq!(o.regressions, 0, "{}", render(&o));
        assert!(
            o.notes.contains(
                &"not compared: `regular(n=a)` on s failed in the baseline (overflow: x)"
                    .to_string()
            ),
            "{:?}",
            o.notes
        );
    }

    #[test]
    fn regressions_are_caught_and_unchanged_rows_pass() {
        let max = parse_max(DEFAULT_MAX).unwrap();
        let base = vec![row("a", 100.0, 10, 0.010), row("b", 50.0, 4, 0.020)];
        assert_eq!(check(&base, &base, &max).regressions, 0);
        // Within tolerance: 9% slower, 1% more error.
        let near = vec![row("a", 109.0, 10, 0.0101), row("b", 50.0, 4, 0.020)];
        assert_eq!(check(&base, &near, &max).regressions, 0);
        // Twice the maps and 20% slower: two regressions on one row.
        let slow = vec![row("a", 120.0, 20, 0.010), row("b", 50.0, 4, 0.020)];
        let o = check(&base, &slow, &max);
        assert_eq!(o.regressions, 2, "{}", render(&o));
        assert!(render(&o).contains("REGRESSION"));
        // Worse error; a missing row.
        let worse = vec![row("a", 100.0, 10, 0.012)];
        let o = check(&base, &worse, &max);
        assert_eq!(o.regressions, 2, "{}", render(&o));
        // Another adapter: the 20% slower time is not judged, and the note says why.
        let mut other = slow.clone();
        for r in &mut other {
            r.core.adapter = serde_json::json!({ "name": "other" });
            r.core.maps = 10;
        }
        other[1].core.maps = 4;
        let o = check(&base, &other, &max);
        assert_eq!(o.regressions, 0, "{}", render(&o));
        assert!(
            o.notes
                .iter()
                .any(|n| n.starts_with("timing not compared: the adapters differ")),
            "{:?}",
            o.notes
        );
    }
}
