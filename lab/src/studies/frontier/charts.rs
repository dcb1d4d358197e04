//! The frontier chart (docs/frontier.md): RMSE against median frame time on log axes for every
//! fixed setting of one scene, the frontier as a staircase; the error budget's rows and the adaptive
//! settings (both scopes) lead the legend and, with the frontier's settings, carry labels (200 labels would hide the points).

use crate::report::charts::pareto::{pareto_front, pareto_steps};
use crate::report::charts::scatter::{push_point, render, Point, Scatter, Series};
use crate::report::charts::ChartError;

/// One setting.
pub struct FrontierPoint {
    /// Series: `adaptive local`, `regular centred`, … (one colour each).
    pub kind: String,
    pub label: String,
    pub ms: f64,
    pub ms_span: (f64, f64),
    pub rmse: f64,
    pub on_frontier: bool,
}

/// Series order: adaptive first (the palette's strongest colours), then the rest as they come.
fn rank(kind: &str) -> usize {
    if kind == BUDGET {
        0
    } else if kind.starts_with("adaptive local") {
        1
    } else if kind.starts_with("adaptive global") {
        2
    } else {
        3
    }
}

/// The series of the error budget's rows: drawn and labelled, but not part of the staircase.
const BUDGET: &str = "error budget";

pub fn frontier_svg(scene: &str, points: &[FrontierPoint]) -> Result<String, ChartError> {
    let usable: Vec<&FrontierPoint> = points
        .iter()
        .filter(|p| p.ms.is_finite() && p.ms > 0.0 && p.rmse.is_finite())
        .collect();
    if usable.is_empty() {
        return Err(ChartError::NoData(
            "needs settings with a positive time and a finite RMSE",
        ));
    }
    let mut ordered = usable.clone();
    ordered.sort_by_key(|p| rank(&p.kind));
    let mut series: Vec<Series> = Vec::new();
    for p in &ordered {
        let labelled = p.on_frontier || rank(&p.kind) < 3;
        let point = Point {
            x: p.ms,
            y: p.rmse,
            label: labelled.then(|| p.label.clone()),
            x_span: (p.ms_span.0 > 0.0 && p.ms_span.1.is_finite()).then_some(p.ms_span),
            hit: None,
        };
        push_point(&mut series, p.kind.clone(), point);
    }
    let pts: Vec<(f64, f64)> = usable
        .iter()
        .filter(|p| p.kind != BUDGET)
        .map(|p| (p.ms, p.rmse))
        .collect();
    render(&Scatter {
        title: format!("{scene}: every fixed setting, the frontier as a staircase"),
        x_desc: "median frame time (ms, wall clock), log scale; whiskers: min–max".into(),
        y_desc: "RMSE of visibility V (log scale)".into(),
        series,
        connect: false,
        front: Some(pareto_steps(&pts, &pareto_front(&pts))),
        front_label: "Pareto front",
        x_log: true,
        y_log: true,
    })
}
