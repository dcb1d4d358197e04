//! Chart (a): RMSE against median frame time, every point labelled, Pareto front as a staircase.

use super::pareto::{pareto_front, pareto_steps};
use super::scatter::{push_point, render, Hit, Point, Scatter, Series};
use super::style::{spans_scenes, with_scene};
use super::{ChartError, ResultRow};
use crate::methods::Family;

/// Points grouped (coloured) by method family (hard, pcf family, filtered maps, multi-sample),
/// multi-sample split by method, so regular grids and adaptive settings read apart on the front;
/// whiskers span min..max time; labels are `label()`.
pub fn error_vs_time_svg(rows: &[ResultRow]) -> Result<String, ChartError> {
    let rows: Vec<&ResultRow> = rows
        .iter()
        .filter(|r| {
            r.core.frame_ms.is_finite() && r.core.frame_ms > 0.0 && r.metrics.rmse.is_finite()
        })
        .collect();
    if rows.is_empty() {
        return Err(ChartError::NoData(
            "needs rows with a positive time and a finite RMSE",
        ));
    }
    let multi = spans_scenes(rows.iter().copied());
    let mut series: Vec<Series> = Vec::new();
    for r in &rows {
        let family = Family::of_name(&r.core.method);
        let group = match family {
            Family::MultiSample => format!("{} ({})", family.title(), r.core.method),
            _ => family.title().to_string(),
        };
        let name = with_scene(multi, &r.core.scene, &group);
        let point = Point {
            x: r.core.frame_ms,
            y: r.metrics.rmse,
            label: Some(r.label()),
            x_span: (r.frame_ms_min.is_finite()
                && r.frame_ms_max.is_finite()
                && r.frame_ms_min > 0.0)
                .then_some((r.frame_ms_min, r.frame_ms_max)),
            hit: Some(Hit::of(r)),
        };
        push_point(&mut series, name, point);
    }
    // A front across scenes would compare unlike things, so draw it only for one scene.
    let front = (!multi).then(|| {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .map(|r| (r.core.frame_ms, r.metrics.rmse))
            .collect();
        pareto_steps(&pts, &pareto_front(&pts))
    });
    render(&Scatter {
        title: "Error against time (lower left is better)".into(),
        x_desc: "median frame time (ms), log scale; whiskers: min–max".into(),
        y_desc: "RMSE of visibility V (log scale)".into(),
        series,
        connect: false,
        front,
        front_label: "Pareto front",
        x_log: true,
        y_log: true,
    })
}
