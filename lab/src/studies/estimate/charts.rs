//! The error estimate's check (docs/error-estimate.md): predicted against measured RMSE of V on
//! log axes, one series per grid layout, the line where they agree.

use crate::report::charts::scatter::{push_point, render, Point, Scatter, Series};
use crate::report::charts::ChartError;

/// One (scene, setting) pair.
pub struct EstimatePoint {
    /// Series: the grid's layout.
    pub layout: String,
    pub label: String,
    pub measured: f64,
    pub predicted: f64,
}

pub fn estimate_svg(points: &[EstimatePoint]) -> Result<String, ChartError> {
    let usable: Vec<&EstimatePoint> = points
        .iter()
        .filter(|p| {
            p.measured > 0.0
                && p.predicted > 0.0
                && p.measured.is_finite()
                && p.predicted.is_finite()
        })
        .collect();
    if usable.is_empty() {
        return Err(ChartError::NoData(
            "needs pairs with a positive measured and predicted RMSE",
        ));
    }
    let mut series: Vec<Series> = Vec::new();
    for p in &usable {
        // Pairs outside [0.8, 1.25] carry their name, so the misses can be read off the chart.
        let ratio = p.predicted / p.measured;
        let label = (!(0.8..=1.25).contains(&ratio)).then(|| p.label.clone());
        push_point(
            &mut series,
            p.layout.clone(),
            Point {
                x: p.measured,
                y: p.predicted,
                label,
                x_span: None,
                hit: None,
            },
        );
    }
    let lo = usable
        .iter()
        .map(|p| p.measured.min(p.predicted))
        .fold(f64::INFINITY, f64::min);
    let hi = usable
        .iter()
        .map(|p| p.measured.max(p.predicted))
        .fold(0.0, f64::max);
    render(&Scatter {
        title: "Predicted against measured RMSE of V (named: outside 0.8–1.25×)".into(),
        x_desc: "measured RMSE against the continuous reference (log scale)".into(),
        y_desc: "predicted RMSE, no reference (log scale)".into(),
        series,
        connect: false,
        front: Some(vec![(lo, lo), (hi, hi)]),
        front_label: "predicted = measured",
        x_log: true,
        y_log: true,
    })
}
