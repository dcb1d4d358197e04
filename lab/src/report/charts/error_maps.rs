//! Chart (c): RMSE against the number of shadow maps, one line per method.

use super::scatter::{push_point, render, Hit, Point, Scatter, Series};
use super::style::{spans_scenes, with_scene};
use super::{ChartError, ResultRow};
use crate::methods::Family;

/// Rows with no shadow map (e.g. a ray-traced reference) are left out.
pub fn error_vs_maps_svg(rows: &[ResultRow]) -> Result<String, ChartError> {
    let multi = spans_scenes(rows.iter());
    let mut series: Vec<Series> = Vec::new();
    for r in rows
        .iter()
        .filter(|r| r.core.maps > 0 && r.metrics.rmse.is_finite())
    {
        let name = with_scene(
            multi,
            &r.core.scene,
            Family::of_name(&r.core.method).title(),
        );
        let point = Point {
            x: f64::from(r.core.maps),
            y: r.metrics.rmse,
            label: Some(r.label()),
            x_span: None,
            hit: Some(Hit::of(r)),
        };
        push_point(&mut series, name, point);
    }
    if series.is_empty() {
        return Err(ChartError::NoData(
            "needs rows with at least one shadow map",
        ));
    }
    render(&Scatter {
        title: "Error against number of shadow maps".into(),
        x_desc: "shadow maps rendered (log scale)".into(),
        y_desc: "RMSE of visibility V (log scale)".into(),
        series,
        connect: true,
        front: None,
        front_label: "Pareto front",
        x_log: true,
        y_log: true,
    })
}
