//! Environment-lighting charts: RMSE against time and against samples with one series per method
//! (not per family: the four environment methods share one), one line per scene.

use super::scatter::{push_point, render, Point, Scatter, Series};
use super::style::{spans_scenes, with_scene};
use super::{ChartError, ResultRow};

/// Which x axis.
#[derive(Clone, Copy, Debug)]
pub enum EnvAxis {
    /// Median frame wall clock.
    Time,
    /// Light samples: pixel lights, median-cut maps or quadtree leaves (rays or maps per pixel).
    Samples,
}

pub fn env_chart_svg(rows: &[ResultRow], axis: EnvAxis) -> Result<String, ChartError> {
    let multi = spans_scenes(rows.iter());
    let mut series: Vec<Series> = Vec::new();
    for r in rows.iter().filter(|r| r.metrics.rmse.is_finite() && r.metrics.rmse > 0.0) {
        let x = match axis {
            EnvAxis::Time => r.total_ms,
            EnvAxis::Samples if r.shadow_maps > 0 => f64::from(r.shadow_maps),
            EnvAxis::Samples => continue,
        };
        let point = Point { x, y: r.metrics.rmse, label: Some(r.label()), x_span: None };
        // ssao=on is its own series: a method with a different term, not another sample count.
        let key = if r.label().contains("ssao=on") { format!("{} + ssao", r.method) } else { r.method.clone() };
        push_point(&mut series, with_scene(multi, &r.scene, &key), point);
    }
    if series.is_empty() {
        return Err(ChartError::NoData("needs environment rows"));
    }
    let (title, x_desc) = match axis {
        EnvAxis::Time => ("Environment: error against time", "median frame time, ms, wall clock (log scale)"),
        EnvAxis::Samples => ("Environment: error against samples", "light samples: pixel lights, median-cut maps or quadtree leaves (log scale)"),
    };
    render(&Scatter { title: title.into(), x_desc: x_desc.into(), y_desc: "RMSE of V (log scale)".into(), series, connect: true, front: None, x_log: true, y_log: true })
}
