//! The cascade study's chart: error against the number of cascades, one line per split scheme.

use crate::report::charts::scatter::{push_point, render, Point, Scatter};
use crate::report::charts::ChartError;

/// One measured setting of the cascade study.
pub struct CascadePoint {
    /// The split scheme, e.g. `practical (λ = 0.5)`: one line each.
    pub scheme: String,
    pub n: u32,
    pub rmse: f64,
}

pub fn cascades_svg(scene: &str, points: &[CascadePoint]) -> Result<String, ChartError> {
    let mut series = Vec::new();
    for p in points.iter().filter(|p| p.rmse.is_finite() && p.rmse > 0.0) {
        push_point(
            &mut series,
            p.scheme.clone(),
            Point {
                x: p.n as f64,
                y: p.rmse,
                label: None,
                x_span: None,
                hit: None,
            },
        );
    }
    if series.is_empty() {
        return Err(ChartError::NoData(
            "needs settings with a finite, non-zero error",
        ));
    }
    for s in &mut series {
        s.points.sort_by(|a, b| a.x.total_cmp(&b.x));
    }
    render(&Scatter {
        title: format!("Error against the number of cascades: {scene}"),
        x_desc: "cascades".into(),
        y_desc: "RMSE of V over geometry pixels (continuous reference, log scale)".into(),
        series,
        connect: true,
        front: None,
        front_label: "Pareto front",
        x_log: false,
        y_log: true,
    })
}
