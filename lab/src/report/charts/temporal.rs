//! Per-frame charts of a sequence: one line per method over the frame index (error, popping,
//! shadow maps per frame).

use super::scatter::{render, Point, Scatter, Series};
use super::ChartError;

/// One named line: (frame index, value) points.
pub struct FrameSeries {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// A line chart over frames on linear axes; non-finite values are left out.
pub fn per_frame_svg(
    title: &str,
    y_desc: &str,
    series: &[FrameSeries],
) -> Result<String, ChartError> {
    let series: Vec<Series> = series
        .iter()
        .map(|s| Series {
            name: s.name.clone(),
            points: s
                .points
                .iter()
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .map(|&(x, y)| Point {
                    x,
                    y,
                    label: None,
                    x_span: None,
                    hit: None,
                })
                .collect(),
        })
        .filter(|s| !s.points.is_empty())
        .collect();
    if series.is_empty() {
        return Err(ChartError::NoData(
            "needs at least one finite per-frame value",
        ));
    }
    render(&Scatter {
        title: title.into(),
        x_desc: "frame".into(),
        y_desc: y_desc.into(),
        series,
        connect: true,
        front: None,
        front_label: "Pareto front",
        x_log: false,
        y_log: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_line_per_series_and_no_data_is_an_error() {
        let s = |name: &str, ys: &[f64]| FrameSeries {
            name: name.into(),
            points: ys.iter().enumerate().map(|(i, &y)| (i as f64, y)).collect(),
        };
        let svg = per_frame_svg(
            "Error per frame",
            "RMSE of V",
            &[
                s("hard", &[0.05, 0.06, 0.055]),
                s("adaptive:p_m=0", &[0.02, f64::NAN, 0.03]),
            ],
        )
        .unwrap();
        assert!(
            svg.starts_with("<svg")
                && svg.contains("hard")
                && svg.contains("adaptive:p_m=0")
                && svg.contains("Error per frame")
        );
        // One connecting line per series, in the series' colour (grid lines are grey polylines).
        let lines = |rgb: &str| {
            svg.to_lowercase()
                .split("<polyline")
                .filter(|p| p.split('>').next().unwrap_or("").contains(rgb))
                .count()
        };
        assert_eq!(lines("stroke=\"#1f77b4\""), 1, "hard's line");
        assert_eq!(lines("stroke=\"#ff7f0e\""), 1, "adaptive's line");
        assert!(matches!(
            per_frame_svg("t", "y", &[s("x", &[f64::NAN])]),
            Err(ChartError::NoData(_))
        ));
    }
}
