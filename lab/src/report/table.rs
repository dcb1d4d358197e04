//! The results table: one row per run, numbers formatted, the best value per column flagged.

use crate::methods::Family;
use serde::Serialize;

use crate::report::charts::ResultRow;

#[derive(Debug, Clone, Serialize)]
pub(super) struct Cell {
    pub text: String,
    pub best: bool,
}

#[derive(Debug, Clone, Serialize)]
pub(super) struct Table {
    pub scene: String,
    /// `speed` or `accuracy`: two narrow tables read better than one that scrolls.
    pub kind: &'static str,
    pub header: Vec<&'static str>,
    pub rows: Vec<Vec<Cell>>,
}

#[derive(Clone, Copy, PartialEq)]
enum Better {
    Lower,
    Higher,
}

/// A numeric column: NaN means "no value" (shown as –, never best).
struct Column {
    name: &'static str,
    better: Better,
    value: fn(&ResultRow) -> f64,
    format: fn(f64) -> String,
}

fn fixed2(v: f64) -> String {
    format!("{v:.2}")
}
fn fixed4(v: f64) -> String {
    format!("{v:.4}")
}
fn int(v: f64) -> String {
    format!("{v:.0}")
}
fn percent(v: f64) -> String {
    format!("{:.2}%", 100.0 * v)
}
/// Errors span decades: four decimals, scientific below 0.001.
fn error(v: f64) -> String {
    if v != 0.0 && v.abs() < 1e-3 {
        format!("{v:.2e}")
    } else {
        format!("{v:.4}")
    }
}
fn db(v: f64) -> String {
    if v == f64::INFINITY {
        "∞".into()
    } else {
        format!("{v:.2}")
    }
}

const LOWER: Better = Better::Lower;
const HIGHER: Better = Better::Higher;

fn col(
    name: &'static str,
    better: Better,
    value: fn(&ResultRow) -> f64,
    format: fn(f64) -> String,
) -> Column {
    Column {
        name,
        better,
        value,
        format,
    }
}

/// Cost: how many maps, waits and milliseconds a frame takes.
fn speed_columns() -> Vec<Column> {
    vec![
        col("maps", LOWER, |r| f64::from(r.core.maps), int),
        col("syncs", LOWER, |r| f64::from(r.syncs), int),
        col("median ms", LOWER, |r| r.core.frame_ms, fixed2),
        col("min ms", LOWER, |r| r.frame_ms_min, fixed2),
        col("max ms", LOWER, |r| r.frame_ms_max, fixed2),
        col(
            "setup ms",
            LOWER,
            |r| r.setup_ms.unwrap_or(f64::NAN),
            fixed2,
        ),
    ]
}

/// Error against the reference.
fn accuracy_columns() -> Vec<Column> {
    vec![
        col("RMSE", LOWER, |r| r.metrics.rmse, error),
        col("MAE", LOWER, |r| r.metrics.mae, error),
        col("max err", LOWER, |r| r.metrics.max_abs, error),
        // Infinite PSNR (identical images) is stored as None.
        col(
            "PSNR dB",
            HIGHER,
            |r| r.metrics.psnr.unwrap_or(f64::INFINITY),
            db,
        ),
        col("SSIM", HIGHER, |r| r.metrics.ssim, fixed4),
        col("FLIP mean", LOWER, |r| r.metrics.flip_mean, fixed4),
        col("FLIP p95", LOWER, |r| r.metrics.flip_p95, fixed4),
        col("FLIP p99", LOWER, |r| r.metrics.flip_p99, fixed4),
        col(
            "penumbra RMSE",
            LOWER,
            |r| r.metrics.penumbra_rmse.unwrap_or(f64::NAN),
            error,
        ),
        col("bad share", LOWER, |r| r.metrics.bad_pixel_share, percent),
        col("NaN", LOWER, |r| r.metrics.nan_count as f64, int),
    ]
}

/// The distinct scenes, in first-appearance order (every per-scene table follows it).
pub(super) fn scenes<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<&'a str> {
    let mut scenes: Vec<&str> = Vec::new();
    for s in names {
        if !scenes.contains(&s) {
            scenes.push(s);
        }
    }
    scenes
}

/// Two tables (speed, accuracy) per scene, scenes in first-appearance order.
pub(super) fn tables(rows: &[ResultRow]) -> Vec<Table> {
    scenes(rows.iter().map(|r| r.core.scene.as_str()))
        .into_iter()
        .flat_map(|scene| {
            // Grouped by family (hard, pcf family, filtered maps, multi-sample), in order within each.
            let mut group: Vec<&ResultRow> =
                rows.iter().filter(|r| r.core.scene == scene).collect();
            group.sort_by_key(|r| Family::of_name(&r.core.method));
            [
                table(scene, "speed", speed_columns(), &group),
                table(scene, "accuracy", accuracy_columns(), &group),
            ]
        })
        .collect()
}

/// Per scene with failed settings: one table of them, each with its reason ("failed: reason").
pub(super) fn failed_tables(rows: &[ResultRow]) -> Vec<Table> {
    scenes(
        rows.iter()
            .filter(|r| !r.measured())
            .map(|r| r.core.scene.as_str()),
    )
    .into_iter()
    .map(|scene| Table {
        scene: scene.to_string(),
        kind: "failed settings",
        header: vec!["method", "outcome"],
        rows: rows
            .iter()
            .filter(|r| r.core.scene == scene)
            .filter_map(|r| {
                r.failed.as_ref().map(|reason| {
                    vec![
                        Cell {
                            text: r.label(),
                            best: false,
                        },
                        Cell {
                            text: format!("failed: {reason}"),
                            best: false,
                        },
                    ]
                })
            })
            .collect(),
    })
    .collect()
}

/// Per scene with certified rows (`--certify K`): each beside its measured RMSE, the bound it
/// was certified at ("RMSE ≤ U at 95% (K px, X ms)"), and whether the bound covered it.
pub(super) fn certified_tables(rows: &[ResultRow]) -> Vec<Table> {
    scenes(
        rows.iter()
            .filter(|r| r.certify.is_some() && r.measured())
            .map(|r| r.core.scene.as_str()),
    )
    .into_iter()
    .map(|scene| Table {
        scene: scene.to_string(),
        kind: "certified error",
        header: vec!["method", "measured RMSE", "certified", "covered"],
        rows: rows
            .iter()
            .filter(|r| r.core.scene == scene && r.measured())
            .filter_map(|r| {
                let c = r.certify.as_ref()?;
                let text = |t: String| Cell {
                    text: t,
                    best: false,
                };
                Some(vec![
                    text(r.label()),
                    text(error(r.metrics.rmse)),
                    text(c.line()),
                    text(if c.bound >= r.metrics.rmse {
                        "yes".into()
                    } else {
                        "no".into()
                    }),
                ])
            })
            .collect(),
    })
    .collect()
}

fn table(scene: &str, kind: &'static str, cols: Vec<Column>, rows: &[&ResultRow]) -> Table {
    let mut header = vec!["family", "method"];
    header.extend(cols.iter().map(|c| c.name));
    let mut cells: Vec<Vec<Cell>> = rows
        .iter()
        .map(|r| {
            vec![
                Cell {
                    text: Family::of_name(&r.core.method).title().to_string(),
                    best: false,
                },
                Cell {
                    text: r.label(),
                    best: false,
                },
            ]
        })
        .collect();
    for c in &cols {
        let values: Vec<f64> = rows.iter().map(|r| (c.value)(r)).collect();
        let best = best_flags(&values, c.better);
        for ((row, v), b) in cells.iter_mut().zip(&values).zip(best) {
            let text = if v.is_nan() {
                "–".to_string()
            } else {
                (c.format)(*v)
            };
            row.push(Cell { text, best: b });
        }
    }
    Table {
        scene: scene.to_string(),
        kind,
        header,
        rows: cells,
    }
}

/// Flags every value equal to the column's best; nothing when all values tie (no contrast).
fn best_flags(values: &[f64], better: Better) -> Vec<bool> {
    let present: Vec<f64> = values.iter().copied().filter(|v| !v.is_nan()).collect();
    let pick = |a: f64, b: f64| {
        if (better == Better::Lower) == (b < a) {
            b
        } else {
            a
        }
    };
    let Some(best) = present.iter().copied().reduce(pick) else {
        return vec![false; values.len()];
    };
    if present.iter().all(|&v| v == best) {
        return vec![false; values.len()];
    }
    values.iter().map(|&v| v == best).collect()
}

/// Settings as (key, value) pairs: top-level keys of an object (sorted), or an array of
/// `[key, value]` pairs (in order); strings unquoted.
pub(super) fn settings_pairs(settings: &serde_json::Value) -> Vec<(String, String)> {
    let text = |v: &serde_json::Value| match v {
        serde_json::Value::String(s) => s.clone(),
        other => other.to_string(),
    };
    let pair = |v: &serde_json::Value| match v.as_array().map(Vec::as_slice) {
        Some([k, v]) => Some((text(k), text(v))),
        _ => None,
    };
    if let Some(pairs) = settings
        .as_array()
        .and_then(|a| a.iter().map(pair).collect::<Option<Vec<_>>>())
    {
        return pairs;
    }
    match settings {
        serde_json::Value::Object(map) => map.iter().map(|(k, v)| (k.clone(), text(v))).collect(),
        serde_json::Value::Null => Vec::new(),
        other => vec![("settings".into(), text(other))],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn best_flags_pick_extremes_and_skip_ties() {
        let nan = f64::NAN;
        assert_eq!(
            best_flags(&[3.0, 1.0, nan, 1.0], Better::Lower),
            vec![false, true, false, true]
        );
        assert_eq!(
            best_flags(&[3.0, f64::INFINITY, 2.0], Better::Higher),
            vec![false, true, false]
        );
        assert_eq!(best_flags(&[0.0, 0.0], Better::Lower), vec![false, false]);
        assert_eq!(best_flags(&[nan], Better::Lower), vec![false]);
    }

    #[test]
    fn number_formats() {
        assert_eq!(error(0.0123456), "0.0123");
        assert_eq!(error(0.00012), "1.20e-4");
        assert_eq!(db(f64::INFINITY), "∞");
        assert_eq!(percent(0.0125), "1.25%");
    }
}
