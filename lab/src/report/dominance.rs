//! The report's "adaptive against the regular grids" tables: per scene, whether some adaptive row
//! is at least as fast and at least as accurate as each regular grid (charts::verdicts), and
//! otherwise how far the nearest adaptive rows miss on time or on error.

use super::table::{scenes, Cell, Table};
use crate::report::charts::{verdicts, DominancePoint, ResultRow};

pub(super) fn tables(rows: &[ResultRow]) -> Vec<Table> {
    let all = verdicts(rows);
    let cell = |text: String, best: bool| Cell { text, best };
    scenes(all.iter().map(|v| v.scene.as_str()))
        .into_iter()
        .map(|scene| {
            let body = all
                .iter()
                .filter(|v| v.scene == scene)
                .map(|v| {
                    let g = &v.regular;
                    let rival = |p: &Option<DominancePoint>| match p {
                        None => "none".to_string(),
                        Some(p) => format!(
                            "{}: {} maps, RMSE {:.5} ({:.3}×), {:.1} ms ({:.2}×)",
                            p.label,
                            p.maps,
                            p.rmse,
                            p.rmse / g.rmse,
                            p.median_ms,
                            p.median_ms / g.median_ms
                        ),
                    };
                    vec![
                        cell(g.label.clone(), false),
                        cell(g.maps.to_string(), false),
                        cell(format!("{:.5}", g.rmse), false),
                        cell(
                            format!("{:.1} ({:.1}–{:.1})", g.median_ms, g.min_ms, g.max_ms),
                            false,
                        ),
                        cell(
                            match (&v.firmly_dominated_by, &v.dominated_by) {
                                (Some(p), _) => format!(
                                    "yes, beyond the spread: {} (slowest {:.1} ms)",
                                    p.label, p.max_ms
                                ),
                                (None, Some(_)) => "yes, within the spread".into(),
                                (None, None) => "no".into(),
                            },
                            v.firmly_dominated_by.is_some(),
                        ),
                        cell(rival(&v.dominated_by), false),
                        cell(rival(&v.fastest_as_accurate), false),
                        cell(rival(&v.most_accurate_as_fast), false),
                    ]
                })
                .collect();
            Table {
                scene: scene.to_string(),
                kind: "adaptive against the regular grids",
                header: vec![
                    "regular grid",
                    "maps",
                    "RMSE",
                    "median ms (min–max)",
                    "dominated",
                    "fastest adaptive as fast and as accurate",
                    "fastest adaptive as accurate",
                    "most accurate adaptive as fast",
                ],
                rows: body,
            }
        })
        .collect()
}
