//! The calibrated estimate's check (docs/budget.md): calibrated predicted against measured RMSE of
//! V on log axes, one series per half of the split (fitting, checking, held out), the pairs under
//! the line (the promise missed) named.

use crate::report::charts::scatter::{push_point, render, Point, Scatter, Series};
use crate::report::charts::ChartError;
use crate::studies::estimate::charts::EstimatePoint;

/// `points`: `layout` names the pair's half (the series), `predicted` is the calibrated figure.
pub fn calibration_svg(title: &str, points: &[EstimatePoint]) -> Result<String, ChartError> {
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
        let label = (p.predicted < p.measured).then(|| p.label.clone());
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
        title: title.into(),
        x_desc: "measured RMSE against the continuous reference (log scale)".into(),
        y_desc: "calibrated predicted RMSE, no reference (log scale)".into(),
        series,
        connect: false,
        front: Some(vec![(lo, lo), (hi, hi)]),
        front_label: "predicted = measured (named: under it)",
        x_log: true,
        y_log: true,
    })
}

/// Which part stops the promise: per pair, the calibrated sampling part over the measured one (x)
/// and the calibrated maps' part over the measured one (y), one series per half; a pair left of
/// x = 1 under-reads its sampling error, under y = 1 its maps' error. `points`: `measured` is x,
/// `predicted` is y, and a non-empty label is drawn (the caller names the pairs whose total is
/// under the measured). The line marks the unit ratios' corner.
pub fn parts_svg(points: &[EstimatePoint]) -> Result<String, ChartError> {
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
        return Err(ChartError::NoData("needs pairs with both parts measured"));
    }
    let mut series: Vec<Series> = Vec::new();
    for p in &usable {
        let label = (!p.label.is_empty()).then(|| p.label.clone());
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
    let hi = usable
        .iter()
        .map(|p| p.measured.max(p.predicted))
        .fold(1.0, f64::max);
    render(&Scatter {
        title: "Each part, calibrated over measured (named: the total under the measured)".into(),
        x_desc: "sampling part: calibrated / measured (log scale)".into(),
        y_desc: "maps' part: calibrated / measured (log scale)".into(),
        series,
        connect: false,
        front: Some(vec![(1.0, hi), (1.0, 1.0), (hi, 1.0)]),
        front_label: "both parts at their measured",
        x_log: true,
        y_log: true,
    })
}
