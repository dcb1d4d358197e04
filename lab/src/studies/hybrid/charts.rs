//! Hybrid-map study chart (docs/hybrid.md): hard-shadow error against map memory.

use crate::report::charts::scatter::{push_point, render, Point, Scatter, Series};
use crate::report::charts::ChartError;

/// One measured map representation.
pub struct MemoryPoint {
    /// `plain` or `hybrid, 2 levels`: one line each.
    pub series: String,
    pub label: String,
    pub bytes_per_map: f64,
    /// Mismatched pixels against the point reference (share).
    pub mismatch_share: f64,
}

pub fn error_memory_svg(points: &[MemoryPoint]) -> Result<String, ChartError> {
    let mut series: Vec<Series> = Vec::new();
    for p in points.iter().filter(|p| p.bytes_per_map > 0.0) {
        let point = Point {
            x: p.bytes_per_map / (1024.0 * 1024.0),
            y: 100.0 * p.mismatch_share,
            label: Some(p.label.clone()),
            x_span: None,
            hit: None,
        };
        push_point(&mut series, p.series.clone(), point);
    }
    if series.is_empty() {
        return Err(ChartError::NoData("no map with a measured size"));
    }
    for s in &mut series {
        s.points.sort_by(|a, b| a.x.total_cmp(&b.x));
    }
    render(&Scatter {
        title: "Hard-shadow error against map memory".into(),
        x_desc: "MiB per shadow map (log scale)".into(),
        y_desc: "mismatched pixels against the point reference (%)".into(),
        series,
        connect: true,
        front: None,
        front_label: "Pareto front",
        x_log: true,
        y_log: false,
    })
}
