//! Environment-lighting charts: RMSE against time and against samples with one series per method
//! and estimator variant (not per family: the four environment methods share one), one line per
//! scene.

use crate::report::charts::scatter::{push_point, render, Point, Scatter, Series};
use crate::report::charts::style::{spans_scenes, with_scene};
use crate::report::charts::{ChartError, ResultRow};

/// Which x axis.
#[derive(Clone, Copy, Debug)]
pub enum EnvAxis {
    /// Median frame wall clock.
    Time,
    /// Light samples: pixel lights, median-cut maps or quadtree leaves (rays or maps per pixel).
    Samples,
}

/// The series a row joins. A variant that is another estimator, not another sample count, is its
/// own line: per vertex (`at=vertex`), a non-box env-shadowmaps filter, and ssao=on.
fn series_key(r: &ResultRow) -> String {
    let mut key = r.core.method.clone();
    if r.core.params.get("at").and_then(|v| v.as_str()) == Some("vertex") {
        key += " per vertex";
    }
    if let Some(f) = r
        .core
        .params
        .get("filter")
        .and_then(|v| v.as_str())
        .filter(|f| *f != "box")
    {
        key += &format!(" {f}");
    }
    if r.label().contains("ssao=on") {
        key += " + ssao";
    }
    key
}

pub fn env_chart_svg(rows: &[ResultRow], axis: EnvAxis) -> Result<String, ChartError> {
    let multi = spans_scenes(rows.iter());
    let mut series: Vec<Series> = Vec::new();
    for r in rows
        .iter()
        .filter(|r| r.metrics.rmse.is_finite() && r.metrics.rmse > 0.0)
    {
        let x = match axis {
            EnvAxis::Time => r.core.frame_ms,
            EnvAxis::Samples if r.core.maps > 0 => f64::from(r.core.maps),
            EnvAxis::Samples => continue,
        };
        let point = Point {
            x,
            y: r.metrics.rmse,
            label: Some(r.label()),
            x_span: None,
            hit: None,
        };
        push_point(
            &mut series,
            with_scene(multi, &r.core.scene, &series_key(r)),
            point,
        );
    }
    if series.is_empty() {
        return Err(ChartError::NoData("needs environment rows"));
    }
    let (title, x_desc) = match axis {
        EnvAxis::Time => (
            "Environment: error against time",
            "median frame time, ms, wall clock (log scale)",
        ),
        EnvAxis::Samples => (
            "Environment: error against samples",
            "light samples: pixel lights, median-cut maps or quadtree leaves (log scale)",
        ),
    };
    render(&Scatter {
        title: title.into(),
        x_desc: x_desc.into(),
        y_desc: "RMSE of V (log scale)".into(),
        series,
        connect: true,
        front: None,
        front_label: "Pareto front",
        x_log: true,
        y_log: true,
    })
}

#[cfg(test)]
mod tests {
    use super::series_key;
    use crate::report::charts::tests::row;
    use serde_json::json;

    #[test]
    fn variants_are_their_own_series() {
        let key = |method: &str, params| series_key(&row(method, params, 128, 1.0, 0.1));
        assert_eq!(
            key(
                "env-pixels",
                json!({"res": [16, 8], "at": "pixel", "ssao": null})
            ),
            "env-pixels"
        );
        assert_eq!(
            key(
                "env-pixels",
                json!({"res": [32, 16], "at": "pixel", "ssao": null})
            ),
            "env-pixels"
        );
        assert_eq!(
            key(
                "env-pixels",
                json!({"res": [16, 8], "at": "vertex", "ssao": null})
            ),
            "env-pixels per vertex"
        );
        assert_eq!(
            key("env-shadowmaps", json!({"k": 16, "filter": "box"})),
            "env-shadowmaps"
        );
        assert_eq!(
            key("env-shadowmaps", json!({"k": 16, "filter": "poisson"})),
            "env-shadowmaps poisson"
        );
    }
}
