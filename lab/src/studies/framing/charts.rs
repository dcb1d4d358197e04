//! Framing study charts: shadow maps, and error, against the penumbra's width on screen.

use crate::report::charts::scatter::{push_point, render, Point, Scatter, Series};
use crate::report::charts::ChartError;

/// One measured run of the framing study.
pub struct WidthPoint {
    /// One line per method and scene, e.g. `bunny: adaptive:preset=seed`.
    pub series: String,
    /// Median penumbra width in pixels (`framing::width`).
    pub width_px: f64,
    pub maps: f64,
    pub rmse: f64,
}

pub enum WidthAxis {
    Maps,
    Rmse,
}

pub fn framing_svg(points: &[WidthPoint], axis: WidthAxis) -> Result<String, ChartError> {
    let mut series: Vec<Series> = Vec::new();
    for p in points
        .iter()
        .filter(|p| p.width_px.is_finite() && p.width_px > 0.0)
    {
        let y = match axis {
            WidthAxis::Maps => p.maps,
            WidthAxis::Rmse => p.rmse,
        };
        push_point(
            &mut series,
            p.series.clone(),
            Point {
                x: p.width_px,
                y,
                label: None,
                x_span: None,
                hit: None,
            },
        );
    }
    if series.is_empty() {
        return Err(ChartError::NoData(
            "needs runs with a measurable penumbra width",
        ));
    }
    for s in &mut series {
        s.points.sort_by(|a, b| a.x.total_cmp(&b.x));
    }
    let (title, y_desc, y_log) = match axis {
        WidthAxis::Maps => (
            "Shadow maps against the penumbra's width on screen",
            "shadow maps rendered",
            true,
        ),
        WidthAxis::Rmse => (
            "Error against the penumbra's width on screen",
            "RMSE of V (continuous reference)",
            true,
        ),
    };
    render(&Scatter {
        title: title.into(),
        x_desc: "median penumbra width (pixels, log scale)".into(),
        y_desc: y_desc.into(),
        series,
        connect: true,
        front: None,
        front_label: "Pareto front",
        x_log: true,
        y_log,
    })
}
