//! The report's "against the baseline" tables: each row's change from the baseline row with the
//! same scene, method and parameters (as `penumbra check` matches them). Times are compared only
//! when both rows were measured on the same adapter.

use super::table::{scenes, Cell, Table};
use crate::record::regression::{change, row_key};
use crate::report::charts::ResultRow;

pub(super) fn tables(baseline: &[ResultRow], rows: &[ResultRow]) -> Vec<Table> {
    let cell = |text: String| Cell { text, best: false };
    scenes(rows.iter().map(|r| r.core.scene.as_str()))
        .into_iter()
        .map(|scene| {
            let body = rows
                .iter()
                .filter(|r| r.core.scene == scene)
                .map(
                    |r| match baseline.iter().find(|o| row_key(o) == row_key(r)) {
                        None => vec![
                            cell(r.label()),
                            cell("no baseline row".into()),
                            cell("–".into()),
                            cell("–".into()),
                            cell("–".into()),
                            cell("–".into()),
                        ],
                        Some(o) => vec![
                            cell(r.label()),
                            cell(format!("{} → {}", o.core.maps, r.core.maps)),
                            cell(if o.core.adapter == r.core.adapter {
                                change(o.core.frame_ms, r.core.frame_ms)
                            } else {
                                "other adapter".into()
                            }),
                            cell(change(o.metrics.rmse, r.metrics.rmse)),
                            cell(change(o.metrics.flip_mean, r.metrics.flip_mean)),
                            cell(change(o.metrics.bad_pixel_share, r.metrics.bad_pixel_share)),
                        ],
                    },
                )
                .collect();
            Table {
                scene: scene.to_string(),
                kind: "against the baseline",
                header: vec![
                    "method",
                    "maps",
                    "median ms",
                    "RMSE",
                    "FLIP mean",
                    "bad share",
                ],
                rows: body,
            }
        })
        .collect()
}
