//! Report tests: self-containedness of the HTML, the Markdown's files, atomic failure.

use std::path::{Path, PathBuf};

use serde_json::json;

use super::*;
use crate::report::charts::{error_vs_time_svg, stage_breakdown_svg, tests::sample_rows};

fn png(w: u32, h: u32, seed: u8) -> Vec<u8> {
    let img = image::RgbImage::from_fn(w, h, |x, y| {
        image::Rgb([(x * 8) as u8 ^ seed, (y * 8) as u8, seed])
    });
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("penumbra_report_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn images(rows: &[ResultRow]) -> Vec<MethodImages> {
    let reference = png(32, 24, 0);
    rows.iter()
        .enumerate()
        .map(|(i, r)| MethodImages {
            label: r.label(),
            scene: r.core.scene.clone(),
            shaded_png: png(32, 24, i as u8 * 30),
            visibility_png: png(32, 24, i as u8 * 30 + 1),
            abs_error_png: png(32, 24, i as u8 * 30 + 2),
            reference_png: reference.clone(),
            signed_error_png: None,
        })
        .collect()
}

fn write_sample(dir: &Path) -> Vec<ResultRow> {
    let rows = sample_rows();
    let charts = vec![
        (
            "Error against time".to_string(),
            error_vs_time_svg(&rows).unwrap(),
        ),
        (
            "Stage times".to_string(),
            stage_breakdown_svg(&rows).unwrap(),
        ),
    ];
    let settings = json!({"adapter": "llvmpipe (Vulkan)", "scene": "bunny", "resolution": [32, 24], "note": "<b>escaped</b>"});
    write_report(
        dir,
        "Penumbra <test> report",
        &settings,
        &rows,
        &images(&rows),
        &charts,
    )
    .unwrap();
    rows
}

#[test]
fn html_is_self_contained() {
    let dir = scratch_dir("html");
    let rows = write_sample(&dir);
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    for bad in [
        "src=\"http",
        "href=\"http",
        "<script src",
        "<link",
        "http://",
        "https://",
        "url(",
        "@import",
    ] {
        assert!(!html.contains(bad), "HTML contains {bad:?}");
    }
    // One script, inline: the viewer's.
    assert_eq!(html.matches("<script").count(), 1);
    assert!(html.contains(&format!("<script>\n{}", include_str!("viewer.js"))));
    for r in &rows {
        assert!(html.contains(&r.label()), "missing label {}", r.label());
    }
    // Each picture once: the shared reference, then three per method; the charts are inline SVG.
    let imgs = html.matches("<img ").count();
    assert_eq!(imgs, 1 + 3 * rows.len());
    assert_eq!(html.matches("<svg ").count(), 2);
    assert_eq!(
        html.matches("<img src=\"data:image/").count(),
        imgs,
        "every image must be a data URI"
    );
    // One viewer (one reference), an item per method with its figures beside it; every point of
    // the error-against-time chart answers with its row.
    assert_eq!(html.matches("<div class=\"viewer\"").count(), 1);
    assert_eq!(
        html.matches("<div class=\"v-item\"").count(),
        1 + rows.len()
    );
    let r = &rows[0];
    assert!(
        html.contains(&format!(
            "<p class=\"v-figures\">RMSE {:.4} · FLIP {:.4} · ",
            r.metrics.rmse, r.metrics.flip_mean
        )),
        "{html}"
    );
    assert_eq!(
        html.matches("<circle class=\"hit\"").count(),
        rows.iter().filter(|r| r.core.frame_ms > 0.0).count()
    );
    assert!(html.contains(&format!(
        "data-label=\"{}\" data-scene=\"{}\"",
        r.label(),
        r.core.scene
    )));
    assert!(
        html.contains("Penumbra &lt;test&gt; report"),
        "title must be escaped"
    );
    assert!(!html.contains("<b>escaped</b>"));
    assert!(html.contains("class=\"best\""));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn markdown_links_files_that_exist() {
    let dir = scratch_dir("md");
    let rows = write_sample(&dir);
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("| method | maps | syncs | median ms |"));
    assert!(md.contains("| method | RMSE | MAE |"));
    assert!(md.contains("**"), "best values are bold");
    // The grids against adaptive: n=9 dominated by p_m=16 (14 ms, 0.35x), n=17 not.
    assert!(
        md.contains("### bunny: adaptive against the regular grids"),
        "{md}"
    );
    assert!(md.contains("| regular(n=9) | 81 | 0.02000 | 40.0 (36.0–48.0) | **yes, beyond the spread: adaptive(p_m=16, scope=local) (slowest 16.8 ms)** | adaptive(p_m=16, scope=local): 25 maps, RMSE 0.01500 (0.750×), 14.0 ms (0.35×) |"), "{md}");
    assert!(md.contains("| regular(n=17) | 289 | 0.00400 | 140.0 (126.0–168.0) | no | none | none | adaptive(p_m=0, scope=local): 61 maps, RMSE 0.00600 (1.500×), 30.0 ms (0.21×) |"), "{md}");
    let mut links = 0;
    for part in md.split("](").skip(1) {
        let path = &part[..part.find(')').unwrap()];
        assert!(dir.join(path).is_file(), "{path} missing");
        links += 1;
    }
    assert_eq!(links, 2 + 4 * rows.len());
    // The shared reference is written once.
    let refs = std::fs::read_dir(dir.join(FILES_DIR))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with("_reference.png")
        })
        .count();
    assert_eq!(refs, 1);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_input_writes_nothing() {
    let dir = scratch_dir("bad");
    let rows = sample_rows();
    let mut imgs = images(&rows);
    imgs[1].abs_error_png = b"GIF89a".to_vec();
    let err = write_report(&dir, "t", &json!({}), &rows, &imgs, &[]).unwrap_err();
    assert!(
        matches!(
            err,
            ReportError::NotPng {
                which: "abs error",
                ..
            }
        ),
        "{err}"
    );
    assert!(!dir.exists(), "nothing may be written on invalid input");
    let charts = vec![("x".to_string(), "not svg".to_string())];
    assert!(matches!(
        write_report(&dir, "t", &json!({}), &rows, &[], &charts),
        Err(ReportError::NotSvg(_))
    ));
}

#[test]
fn failed_write_leaves_no_partial_file() {
    let dir = scratch_dir("atomic");
    // A directory where report.html should go makes the final rename fail.
    std::fs::create_dir_all(dir.join("report.html").join("occupied")).unwrap();
    let rows = sample_rows();
    let err = write_report(&dir, "t", &json!({}), &rows, &images(&rows), &[]).unwrap_err();
    assert!(matches!(err, ReportError::Io { .. }), "{err}");
    let leftovers: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
