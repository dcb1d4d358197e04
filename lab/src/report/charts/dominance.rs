//! Adaptive against the regular grids, scene by scene: for every `regular` row, the adaptive rows
//! that are at least as fast (median frame) and at least as accurate (RMSE), whether one is faster
//! beyond the repeats' spread, and the two nearest misses. Times are compared only between rows
//! measured on the same adapter.

use serde::Serialize;

use super::ResultRow;

/// One row as the verdicts name it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Point {
    pub label: String,
    pub maps: u32,
    pub rmse: f64,
    pub median_ms: f64,
    pub min_ms: f64,
    pub max_ms: f64,
}

impl Point {
    fn of(r: &ResultRow) -> Self {
        Self {
            label: r.label(),
            maps: r.core.maps,
            rmse: r.metrics.rmse,
            median_ms: r.core.frame_ms,
            min_ms: r.frame_ms_min,
            max_ms: r.frame_ms_max,
        }
    }
}

/// The verdict on one regular grid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verdict {
    pub scene: String,
    pub regular: Point,
    /// The fastest adaptive row with RMSE and median frame both at most the grid's, if any.
    pub dominated_by: Option<Point>,
    /// The fastest adaptive row at most as inaccurate whose slowest frame is at most the grid's
    /// fastest: dominated beyond the spread of the repeats, not only on the medians.
    pub firmly_dominated_by: Option<Point>,
    /// The fastest adaptive row at most as inaccurate as the grid, whatever its time.
    pub fastest_as_accurate: Option<Point>,
    /// The most accurate adaptive row at most as slow as the grid, whatever its error.
    pub most_accurate_as_fast: Option<Point>,
}

/// One verdict per `regular` row of a scene that also has `adaptive` rows on the same adapter, in
/// row order; empty when no scene has both.
pub fn verdicts(rows: &[ResultRow]) -> Vec<Verdict> {
    let usable = |r: &ResultRow| r.core.frame_ms.is_finite() && r.metrics.rmse.is_finite();
    rows.iter()
        .filter(|g| g.core.method == "regular" && usable(g))
        .filter_map(|g| {
            let rivals: Vec<&ResultRow> = rows
                .iter()
                .filter(|a| {
                    a.core.method == "adaptive"
                        && a.core.scene == g.core.scene
                        && a.core.adapter == g.core.adapter
                        && usable(a)
                })
                .collect();
            if rivals.is_empty() {
                return None;
            }
            let accurate = |a: &&&ResultRow| a.metrics.rmse <= g.metrics.rmse;
            let fast = |a: &&&ResultRow| a.core.frame_ms <= g.core.frame_ms;
            // Ties on time go to the more accurate row, ties on error to the faster one.
            let fastest = |it: &mut dyn Iterator<Item = &&ResultRow>| {
                it.min_by(|a, b| {
                    a.core
                        .frame_ms
                        .total_cmp(&b.core.frame_ms)
                        .then(a.metrics.rmse.total_cmp(&b.metrics.rmse))
                })
                .map(|r| Point::of(r))
            };
            let most_accurate = rivals
                .iter()
                .filter(fast)
                .min_by(|a, b| {
                    a.metrics
                        .rmse
                        .total_cmp(&b.metrics.rmse)
                        .then(a.core.frame_ms.total_cmp(&b.core.frame_ms))
                })
                .map(|r| Point::of(r));
            Some(Verdict {
                scene: g.core.scene.clone(),
                regular: Point::of(g),
                dominated_by: fastest(&mut rivals.iter().filter(accurate).filter(fast)),
                firmly_dominated_by: fastest(
                    &mut rivals
                        .iter()
                        .filter(accurate)
                        .filter(|a| a.frame_ms_max <= g.frame_ms_min),
                ),
                fastest_as_accurate: fastest(&mut rivals.iter().filter(accurate)),
                most_accurate_as_fast: most_accurate,
            })
        })
        .collect()
}
