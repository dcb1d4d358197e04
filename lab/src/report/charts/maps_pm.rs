//! Chart (b): shadow maps against the adaptive threshold P_M.

use super::scatter::{push_point, render, Hit, Point, Scatter, Series};
use super::style::{spans_scenes, with_scene};
use super::{params_short, ChartError, ResultRow};

/// Rows with method `adaptive` and a finite numeric `p_m` parameter. P_M = 0 is the seed's
/// setting, so x is P_M + 1 on a log axis (0 lands at 1). One line per scene and per set of
/// the other parameters that vary between the adaptive rows (a parameter every row shares would
/// only lengthen the legend). A non-numeric `p_m` (e.g. the string "inf") is skipped.
pub fn maps_vs_pm_svg(rows: &[ResultRow]) -> Result<String, ChartError> {
    let multi = spans_scenes(rows.iter());
    let adaptive: Vec<&ResultRow> = rows
        .iter()
        .filter(|r| r.core.method == "adaptive")
        .collect();
    let shared = |key: &str| {
        adaptive
            .iter()
            .all(|r| r.core.params.get(key) == adaptive[0].core.params.get(key))
    };
    let mut series: Vec<Series> = Vec::new();
    for r in &adaptive {
        let Some(pm) = r.param_f64("p_m").filter(|&p| p >= 0.0) else {
            continue;
        };
        let mut others = r.core.params.clone();
        if let Some(map) = others.as_object_mut() {
            map.retain(|k, _| k != "p_m" && !shared(k));
        }
        let rest = params_short(&others);
        let key = if rest.is_empty() {
            "adaptive".to_string()
        } else {
            format!("adaptive({rest})")
        };
        let name = with_scene(multi, &r.core.scene, &key);
        let point = Point {
            x: pm + 1.0,
            y: f64::from(r.core.maps),
            label: None,
            x_span: None,
            hit: Some(Hit::of(r)),
        };
        push_point(&mut series, name, point);
    }
    if series.is_empty() {
        return Err(ChartError::NoData(
            "needs adaptive rows with a numeric p_m parameter",
        ));
    }
    render(&Scatter {
        title: "Shadow maps against the threshold P_M (adaptive)".into(),
        x_desc: "P_M + 1 (pixels, log scale; P_M = 0 plotted at 1)".into(),
        y_desc: "shadow maps rendered".into(),
        series,
        connect: true,
        front: None,
        front_label: "Pareto front",
        x_log: true,
        y_log: false,
    })
}
