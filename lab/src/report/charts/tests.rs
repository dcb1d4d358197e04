//! Chart tests: the Pareto front on known points, every chart's SVG text, PNG rasterisation.

use std::collections::BTreeMap;

use serde_json::json;

use super::*;
use crate::metrics::Metrics;

pub(crate) fn metrics(rmse: f64) -> Metrics {
    Metrics {
        rmse,
        mae: rmse * 0.7,
        max_abs: rmse * 5.0,
        psnr: (rmse > 0.0).then(|| -20.0 * rmse.log10()),
        ssim: 1.0 - rmse,
        flip_mean: rmse * 0.5,
        flip_p95: rmse * 2.0,
        flip_p99: rmse * 3.0,
        penumbra_rmse: Some(rmse * 2.0),
        bad_pixel_share: rmse,
        nan_count: 0,
        pixels: 1000,
        penumbra_pixels: 200,
        mismatch_share: rmse,
    }
}

pub(crate) fn row(
    method: &str,
    params: serde_json::Value,
    maps: u32,
    ms: f64,
    rmse: f64,
) -> ResultRow {
    let stages: BTreeMap<String, f64> = [
        ("gbuffer", 0.2 * ms),
        ("shadow_raster", 0.5 * ms),
        ("shade", 0.3 * ms),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    ResultRow {
        core: crate::record::RowCore {
            scene: "bunny".into(),
            method: method.into(),
            params,
            adapter: json!({"name": "llvmpipe", "backend": "vulkan"}),
            maps,
            rmse,
            frame_ms: ms,
            ..Default::default()
        },
        frame_ms_min: ms * 0.9,
        frame_ms_max: ms * 1.2,
        stages_ms: stages,
        metrics: metrics(rmse),
        ..Default::default()
    }
}

/// A plausible sweep: hard shadows, PCF, regular grids and adaptive at several P_M.
pub(crate) fn sample_rows() -> Vec<ResultRow> {
    vec![
        row("hard", json!({}), 1, 2.0, 0.2),
        row("pcf", json!({"kernel": 5}), 1, 2.5, 0.12),
        row("regular", json!({"n": 9}), 81, 40.0, 0.02),
        row("regular", json!({"n": 17}), 289, 140.0, 0.004),
        row(
            "adaptive",
            json!({"p_m": 0, "scope": "local"}),
            61,
            30.0,
            0.006,
        ),
        row(
            "adaptive",
            json!({"p_m": 16, "scope": "local"}),
            25,
            14.0,
            0.015,
        ),
        row(
            "adaptive",
            json!({"p_m": 256, "scope": "local"}),
            9,
            7.0,
            0.05,
        ),
    ]
}

#[test]
fn pareto_known_points() {
    let nan = f64::NAN;
    let pts = [
        (1.0, 5.0),
        (2.0, 3.0),
        (3.0, 4.0),
        (4.0, 1.0),
        (2.0, 3.0),
        (5.0, 1.0),
        (0.5, 10.0),
        (nan, 0.0),
    ];
    let front = pareto_front(&pts);
    assert_eq!(front, vec![6, 0, 1, 3]);
    let steps = pareto_steps(&pts, &front);
    assert_eq!(
        steps,
        vec![
            (0.5, 10.0),
            (1.0, 10.0),
            (1.0, 5.0),
            (2.0, 5.0),
            (2.0, 3.0),
            (4.0, 3.0),
            (4.0, 1.0)
        ]
    );
    assert!(pareto_front(&[]).is_empty());
    // Same x, different y: only the lower one is on the front.
    assert_eq!(pareto_front(&[(1.0, 2.0), (1.0, 1.0)]), vec![1]);
}

#[test]
fn labels_are_short() {
    let r = &sample_rows()[4];
    assert_eq!(r.label(), "adaptive(p_m=0, scope=local)");
    assert_eq!(sample_rows()[0].label(), "hard");
}

fn assert_svg(svg: &str, needles: &[&str]) {
    assert!(
        svg.starts_with("<svg") && svg.len() > 1000,
        "not an SVG: {:.200}",
        svg
    );
    for n in needles {
        assert!(svg.contains(n), "SVG lacks {n:?}");
    }
}

#[test]
fn error_vs_time_has_every_label_and_the_front() {
    let rows = sample_rows();
    let svg = error_vs_time_svg(&rows).unwrap();
    let labels: Vec<String> = rows.iter().map(|r| r.label()).collect();
    let mut needles: Vec<&str> = labels.iter().map(String::as_str).collect();
    needles.extend([
        "Error against time",
        "median frame time (ms)",
        "RMSE",
        "Pareto front",
    ]);
    assert_svg(&svg, &needles);
}

#[test]
fn maps_vs_pm_uses_adaptive_rows_only() {
    let svg = maps_vs_pm_svg(&sample_rows()).unwrap();
    // Every adaptive row has scope=local: the legend leaves it out.
    assert_svg(&svg, &["P_M + 1", "shadow maps rendered", ">\nadaptive\n<"]);
    // (The points' marks, after the drawing, name each row in full.)
    let drawn = svg.split("<g class=\"hits\">").next().unwrap();
    assert!(!drawn.contains("scope=local"));
    let mut rows = sample_rows();
    rows.push(row(
        "adaptive",
        json!({"p_m": 0, "scope": "global"}),
        70,
        40.0,
        0.006,
    ));
    assert_svg(
        &maps_vs_pm_svg(&rows).unwrap(),
        &["adaptive(scope=local)", "adaptive(scope=global)"],
    );
    let no_adaptive: Vec<ResultRow> = sample_rows()
        .into_iter()
        .filter(|r| r.core.method != "adaptive")
        .collect();
    assert!(matches!(
        maps_vs_pm_svg(&no_adaptive),
        Err(ChartError::NoData(_))
    ));
}

#[test]
fn every_point_of_error_against_time_answers_with_its_row() {
    let rows = sample_rows();
    let svg = error_vs_time_svg(&rows).unwrap();
    let hits = svg
        .split("<g class=\"hits\">")
        .nth(1)
        .expect("a group of marks");
    assert_eq!(hits.matches("<circle class=\"hit\"").count(), rows.len());
    assert!(
        svg.trim_end().ends_with("</g>\n</svg>") || svg.trim_end().ends_with("</g></svg>"),
        "the marks are drawn last, on top"
    );
    let r = &rows[2];
    let mark = hits
        .split("<circle")
        .find(|m| m.contains(&format!("data-label=\"{}\"", r.label())))
        .expect("the row's mark");
    assert!(
        mark.contains(&format!(
            "<title>{} ({})\n{} maps · RMSE {:.4} · FLIP {:.4} · {:.2} ms",
            r.label(),
            r.core.scene,
            r.core.maps,
            r.metrics.rmse,
            r.metrics.flip_mean,
            r.core.frame_ms
        )),
        "{mark}"
    );
    assert!(
        mark.contains("tabindex=\"0\"") && mark.contains("fill-opacity=\"0\""),
        "{mark}"
    );
    // The PNG draws nothing of them: the same pixels as without the marks.
    let bare = svg.split("<g class=\"hits\">").next().unwrap().to_string() + "</svg>\n";
    assert_eq!(
        svg_to_png(&svg, 1.0).unwrap(),
        svg_to_png(&bare, 1.0).unwrap()
    );
}

#[test]
fn error_vs_maps_has_axes_and_methods() {
    let svg = error_vs_maps_svg(&sample_rows()).unwrap();
    assert_svg(
        &svg,
        &["shadow maps rendered", "RMSE", "regular", "adaptive", "pcf"],
    );
    assert!(matches!(error_vs_maps_svg(&[]), Err(ChartError::NoData(_))));
}

#[test]
fn frame_split_sums_stages_into_four_parts() {
    let rows = sample_rows();
    let svg = frame_split_svg(&rows).unwrap();
    assert_svg(
        &svg,
        &["Frame split", "raster", "decision", "shade", "waits"],
    );
    assert!(
        !svg.contains("Stage time breakdown"),
        "the frame split carries the stage chart's title"
    );
    for stage in rows[0].stages_ms.keys() {
        assert!(
            !svg.contains(&format!(">{stage}<")) || ["shade"].contains(&stage.as_str()),
            "stage {stage} drawn on its own"
        );
    }
}

#[test]
fn stage_breakdown_has_rows_and_stages() {
    let rows = sample_rows();
    let svg = stage_breakdown_svg(&rows).unwrap();
    let labels: Vec<String> = rows.iter().map(|r| r.label()).collect();
    let mut needles: Vec<&str> = labels.iter().map(String::as_str).collect();
    needles.extend([
        "gbuffer",
        "shadow_raster",
        "shade",
        "time (ms)",
        "Stage time breakdown",
    ]);
    assert_svg(&svg, &needles);
}

#[test]
fn zero_rmse_falls_back_to_linear_axis() {
    let mut rows = sample_rows();
    rows[3].metrics.rmse = 0.0;
    assert!(error_vs_time_svg(&rows).is_ok());
}

/// Dark pixels of a decoded PNG (text, axes, markers all qualify).
fn dark_pixels(png: &[u8]) -> (u32, u32, usize) {
    let img = image::load_from_memory_with_format(png, image::ImageFormat::Png)
        .unwrap()
        .to_rgb8();
    let dark = img
        .pixels()
        .filter(|p| p.0.iter().all(|&c| c < 100))
        .count();
    (img.width(), img.height(), dark)
}

#[test]
fn text_renders_in_png() {
    // Text only: dark pixels prove `sans-serif` resolved to the embedded face (no system font used).
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="50"><text x="10" y="35" font-family="sans-serif" font-size="24">Penumbra</text></svg>"#;
    let (w, h, dark) = dark_pixels(&svg_to_png(svg, 1.0).unwrap());
    assert_eq!((w, h), (200, 50));
    assert!(
        dark > 50,
        "text did not render ({dark} dark pixels): the embedded DejaVu Sans was not used"
    );
}

#[test]
fn chart_png_decodes_and_is_not_uniform() {
    let svg = error_vs_time_svg(&sample_rows()).unwrap();
    let png = svg_to_png(&svg, 2.0).unwrap();
    let (w, h, dark) = dark_pixels(&png);
    assert_eq!((w, h), (1920, 1280));
    assert!(dark > 1000, "{dark} dark pixels");
    assert!(matches!(
        svg_to_png(&svg, 0.0),
        Err(ChartError::BadScale(_))
    ));
    assert!(matches!(
        svg_to_png("not svg", 1.0),
        Err(ChartError::Svg(_))
    ));
}

/// Every chart renders to an SVG file and a PNG that decodes at a sane size.
#[test]
fn every_chart_writes_svg_and_png() {
    let dir = tempfile::tempdir().unwrap();
    let rows = sample_rows();
    let charts = [
        ("error_time", error_vs_time_svg(&rows).unwrap()),
        ("maps_pm", maps_vs_pm_svg(&rows).unwrap()),
        ("error_maps", error_vs_maps_svg(&rows).unwrap()),
        ("stages", stage_breakdown_svg(&rows).unwrap()),
        ("frame_split", frame_split_svg(&rows).unwrap()),
    ];
    for (name, svg) in charts {
        std::fs::write(dir.path().join(format!("{name}.svg")), &svg).unwrap();
        std::fs::write(
            dir.path().join(format!("{name}.png")),
            svg_to_png(&svg, 1.0).unwrap(),
        )
        .unwrap();
        let png = image::open(dir.path().join(format!("{name}.png"))).unwrap();
        assert!(
            png.width() >= 320 && png.height() >= 200,
            "{name}: {}x{}",
            png.width(),
            png.height()
        );
        assert!(
            std::fs::read_to_string(dir.path().join(format!("{name}.svg")))
                .unwrap()
                .starts_with("<svg"),
            "{name}"
        );
    }
}

#[test]
fn log_ticks_and_labels() {
    let (bold, light) = scatter::log_ticks(0.003, 0.25);
    let labels: Vec<String> = bold.iter().map(scatter::tick_label).collect();
    assert_eq!(labels, ["0.005", "0.01", "0.02", "0.05", "0.1", "0.2"]);
    assert!(light.len() > bold.len());
    // A narrow range still gets at least two labelled ticks.
    assert!(scatter::log_ticks(1.1, 4.4).0.len() >= 2);
    assert_eq!(scatter::tick_label(&60.0), "60");
    assert_eq!(scatter::tick_label(&(0.1 + 0.2)), "0.3");
    // A range out to f64's largest (an RMSE of 1e308 padded) or past it: a few labels, no loop
    // over billions of decades.
    for (lo, hi) in [(1e-3, f64::MAX), (1e-300, 1e308), (1e-3, f64::INFINITY)] {
        let (bold, light) = scatter::log_ticks(lo, hi);
        assert!(
            (2..=13).contains(&bold.len()) && light.is_empty(),
            "{lo}..{hi}: {bold:?}"
        );
    }
}

#[test]
fn single_row_charts() {
    let rows = vec![sample_rows().remove(4)];
    assert_svg(
        &stage_breakdown_svg(&rows).unwrap(),
        &["adaptive(p_m=0, scope=local)"],
    );
    assert_svg(
        &error_vs_time_svg(&rows).unwrap(),
        &["adaptive(p_m=0, scope=local)"],
    );
    assert!(maps_vs_pm_svg(&rows).is_ok());
    assert!(error_vs_maps_svg(&rows).is_ok());
}

#[test]
fn dominance_on_known_points() {
    let rows = sample_rows();
    let v = verdicts(&rows);
    // One verdict per regular row, in row order.
    assert_eq!(
        v.iter()
            .map(|v| v.regular.label.as_str())
            .collect::<Vec<_>>(),
        ["regular(n=9)", "regular(n=17)"]
    );
    // n = 9 (40 ms, 0.02): the fastest adaptive row with RMSE <= 0.02 and time <= 40 ms is p_m=16.
    let by = v[0].dominated_by.as_ref().expect("n=9 is dominated");
    assert_eq!((by.maps, by.median_ms, by.rmse), (25, 14.0, 0.015));
    // Its slowest frame (16.8 ms) is under the grid's fastest (36 ms): firmly dominated too.
    assert_eq!(
        v[0].firmly_dominated_by.as_ref().map(|p| p.max_ms),
        Some(14.0 * 1.2)
    );
    // n = 17 (140 ms, 0.004): every adaptive row is faster but none is as accurate.
    assert!(v[1].dominated_by.is_none() && v[1].fastest_as_accurate.is_none());
    let near = v[1]
        .most_accurate_as_fast
        .as_ref()
        .expect("some adaptive row is as fast");
    assert_eq!((near.maps, near.rmse), (61, 0.006));

    // A tie on both counts dominates; a row from another adapter does not take part.
    let mut tie = vec![
        row("regular", json!({"n": 5}), 25, 10.0, 0.03),
        row("adaptive", json!({"p_m": 0}), 25, 10.0, 0.03),
    ];
    assert_eq!(
        verdicts(&tie)[0].dominated_by.as_ref().map(|p| p.maps),
        Some(25)
    );
    // Equal medians with overlapping spreads (9-12 ms each) are not firm.
    assert!(verdicts(&tie)[0].firmly_dominated_by.is_none());
    tie[1].core.adapter = json!({"name": "other"});
    assert!(verdicts(&tie).is_empty());
    // A scene without adaptive rows gets no verdict.
    assert!(verdicts(&rows[..4]).is_empty());
}
