//! `penumbra compare` end to end on a tiny scene: rows, CSV, pictures, charts, a self-contained
//! report, `penumbra report` re-rendering it, and the reference cache shared with `reference`.

mod common;
use common::temp_dir;
use penumbra::research::gpu::stages::{Split, Stage};
use std::path::Path;
use std::process::{Command, Output};

/// The binary with its own reference cache, so tests neither read nor fill the user's.
fn run(cache: &Path, args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(args)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .env("PENUMBRA_CACHE", cache)
        .output()
        .expect("run penumbra binary");
    assert!(
        out.status.success(),
        "penumbra {args:?} failed: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Everything report.html loads must be inside it: no URL, script file, stylesheet link or import;
/// one inline script, the viewer's, which requests nothing.
fn assert_self_contained(html: &str) {
    let lower = html.to_lowercase();
    for bad in [
        "src=\"http",
        "src='http",
        "href=\"http",
        "href='http",
        "<script src",
        "<link",
        "@import",
        "url(",
        "fetch(",
        "xmlhttprequest",
        "http://",
        "https://",
    ] {
        assert!(!lower.contains(bad), "report.html contains {bad:?}");
    }
    assert_eq!(
        lower.matches("<script").count(),
        1,
        "one script: the viewer's"
    );
    for part in lower.split("src=").skip(1) {
        let value = part.trim_start_matches(['"', '\'']);
        assert!(
            value.starts_with("data:image/"),
            "a src is not a data: image URI: {:.60}",
            value
        );
    }
    assert!(!lower.contains("href="), "report.html links elsewhere");
}

#[test]
fn compare_writes_rows_pictures_charts_and_a_self_contained_report() {
    // The GPU must be there: fail with install instructions rather than a process error below.
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let dir = temp_dir("compare_pipeline");
    let (cache, out) = (dir.join("cache"), dir.join("out"));
    let args = [
        "compare",
        "--scene",
        "analytic-square",
        "--set",
        "resolution=64",
        "--methods",
        "hard,regular:n=3,adaptive",
        "--repeats",
        "1",
        "--out",
        out.to_str().unwrap(),
    ];
    let stdout = String::from_utf8_lossy(&run(&cache, &args).stdout).to_string();
    assert!(
        stdout.contains("report:") && stdout.contains("regular:n=3"),
        "{stdout}"
    );

    let jsonl = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    let rows: Vec<serde_json::Value> = jsonl
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let labels: Vec<&str> = rows.iter().map(|r| r["label"].as_str().unwrap()).collect();
    assert_eq!(labels, ["hard", "regular:n=3", "adaptive:p_m=0"]);
    for r in &rows {
        for key in [
            "scene",
            "method",
            "params",
            "adapter",
            "spec",
            "maps",
            "map_size",
            "rmse",
            "frame_ms",
            "version",
            "stages_ms",
            "metrics",
            "syncs",
            "label",
        ] {
            assert!(!r[key].is_null(), "row lacks {key}: {r}");
        }
        for key in [
            "rmse",
            "mae",
            "max_abs",
            "psnr",
            "ssim",
            "flip_mean",
            "flip_p95",
            "flip_p99",
            "penumbra_rmse",
            "bad_pixel_share",
            "nan_count",
        ] {
            assert!(r["metrics"].get(key).is_some(), "metrics lack {key}: {r}");
        }
        assert_eq!(r["scene"], "analytic-square");
        assert_eq!(r["metrics"]["nan_count"], 0);
        assert_eq!(r["rmse"], r["metrics"]["rmse"]);
        assert!(
            r.get("target").is_none(),
            "no method here has a target: {r}"
        );
        assert!(r["frame_ms"].as_f64().unwrap() > 0.0);
        assert!(r["frame_ms_min"].as_f64().unwrap() <= r["frame_ms_max"].as_f64().unwrap());
        assert!(
            r["stages_ms"].as_object().unwrap().contains_key("shade"),
            "{r}"
        );
        for path in r["images"].as_object().unwrap().values() {
            assert!(out.join(path.as_str().unwrap()).is_file(), "missing {path}");
        }
    }
    // Each method's run.json carries the measurement's timing, not its last (frame-mode) frame's
    // waits: the row's median and stages, and a split and decision share over those stages.
    for (r, slug) in rows.iter().zip(["hard", "regular_n_3", "adaptive_p_m_0"]) {
        let path = out.join(format!("images/{slug}/run.json"));
        let run: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
        assert_eq!(run["total_ms"], r["frame_ms"], "{}", path.display());
        assert_eq!(run["stages_ms"], r["stages_ms"], "{}", path.display());
        let split: f64 = run["frame_split_ms"]
            .as_object()
            .unwrap()
            .values()
            .map(|v| v.as_f64().unwrap())
            .sum();
        let stages: f64 = r["stages_ms"]
            .as_object()
            .unwrap()
            .values()
            .map(|v| v.as_f64().unwrap())
            .sum();
        assert!(
            (split - stages).abs() < 1e-6,
            "{}: split {split} ms, stages {stages} ms",
            path.display()
        );
        let share = run["decision_share"].as_f64().unwrap();
        // One definition: the decision share is the split's decision part (the stage table's
        // decision stages) over the stages.
        let decision = r["stages_ms"]
            .as_object()
            .unwrap()
            .iter()
            .filter(|(k, _)| Stage::named(k).is_some_and(|s| s.split == Some(Split::Decision)))
            .map(|(_, v)| v.as_f64().unwrap())
            .sum::<f64>();
        assert_eq!(
            run["decision_stages_ms"],
            run["frame_split_ms"]["decision"],
            "{}",
            path.display()
        );
        assert!(
            (share - decision / stages).abs() < 1e-9,
            "{}: share {share}",
            path.display()
        );
        assert_eq!(
            share > 0.0,
            slug.starts_with("adaptive"),
            "{}: share {share}",
            path.display()
        );
        assert!(
            share.is_sign_positive(),
            "{}: share {share}",
            path.display()
        );
    }
    assert_eq!(rows[0]["maps"], 1);
    assert_eq!(rows[1]["maps"], 9);
    // More light samples, less error than one hard shadow.
    let rmse = |i: usize| rows[i]["metrics"]["rmse"].as_f64().unwrap();
    assert!(
        rmse(1) < rmse(0) && rmse(2) < rmse(0),
        "RMSE hard {} regular {} adaptive {}",
        rmse(0),
        rmse(1),
        rmse(2)
    );

    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4);
    assert!(csv.starts_with("scene,label,spec,method,params,adapter,map_size,maps,"));
    for f in [
        "reference.exr",
        "reference.png",
        "reference_shaded.png",
        "charts/error_vs_time.png",
        "charts/error_vs_time.svg",
        "charts/stage_breakdown.png",
        "charts/frame_split.svg",
        "report.md",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }

    // One verdict, on the one regular grid; the adaptive row dominates it exactly when it is at
    // most as slow and at most as inaccurate in the rows just read.
    let dominance: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("dominance.json")).unwrap())
            .unwrap();
    let verdicts = dominance.as_array().unwrap();
    assert_eq!(verdicts.len(), 1, "{dominance}");
    assert_eq!(verdicts[0]["regular"]["label"], "regular:n=3");
    let ms = |i: usize| rows[i]["frame_ms"].as_f64().unwrap();
    let dominated = rmse(2) <= rmse(1) && ms(2) <= ms(1);
    assert_eq!(
        !verdicts[0]["dominated_by"].is_null(),
        dominated,
        "{dominance}"
    );
    assert_eq!(
        verdicts[0]["fastest_as_accurate"]["label"].as_str(),
        (rmse(2) <= rmse(1)).then_some("adaptive:p_m=0"),
        "{dominance}"
    );

    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert_self_contained(&html);
    for label in labels {
        assert!(html.contains(label), "report lacks {label}");
    }
    // Each picture once: the shared reference, then 4 per method, in one viewer; the charts (4: one
    // p_m, so no P_M chart) inline, each point of the two scatter charts answering with its row.
    let images = html.matches("<img ").count();
    assert_eq!(
        images,
        1 + 4 * rows.len(),
        "the reference + 4 pictures per method"
    );
    assert_eq!(html.matches("<svg ").count(), 4);
    assert_eq!(html.matches("<div class=\"viewer\"").count(), 1);
    assert_eq!(
        html.matches("<circle class=\"hit\"").count(),
        2 * rows.len(),
        "error against time and against maps"
    );

    // `penumbra report` re-renders the same page from the results file alone.
    let again = dir.join("again");
    run(
        &cache,
        &[
            "report",
            out.join("results.jsonl").to_str().unwrap(),
            "--out",
            again.to_str().unwrap(),
        ],
    );
    let html2 = std::fs::read_to_string(again.join("report.html")).unwrap();
    assert_self_contained(&html2);
    assert_eq!(
        html2, html,
        "report from results.jsonl differs from the one compare wrote"
    );

    // The reference compare traced is in the cache: `reference` with the same settings reads it.
    let reference = dir.join("reference");
    let args = [
        "reference",
        "--scene",
        "analytic-square",
        "--set",
        "resolution=64",
        "--out",
        reference.to_str().unwrap(),
    ];
    let stdout = String::from_utf8_lossy(&run(&cache, &args).stdout).to_string();
    assert!(stdout.contains("from the cache"), "{stdout}");
    let record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(reference.join("reference.json")).unwrap()).unwrap();
    assert_eq!(record["cached"], true);
    assert!(reference.join("reference.exr").is_file());
}

#[test]
fn sweep_expands_grids_and_charts_maps_against_p_m() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let dir = temp_dir("sweep_pipeline");
    let (cache, out, spec) = (dir.join("cache"), dir.join("out"), dir.join("spec.toml"));
    std::fs::write(&spec, "methods = [\"hard\"]\n[[grid]]\nmethod = \"adaptive\"\np_m = [0, 1000000]\n[[grid]]\nmethod = \"regular\"\nn = [2, 3]\n").unwrap();
    let args = [
        "sweep",
        "--scene",
        "analytic-square",
        "--set",
        "resolution=48",
        "--spec",
        spec.to_str().unwrap(),
        "--repeats",
        "1",
        "--out",
        out.to_str().unwrap(),
    ];
    run(&cache, &args);
    let jsonl = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    let rows: Vec<serde_json::Value> = jsonl
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let labels: Vec<&str> = rows.iter().map(|r| r["label"].as_str().unwrap()).collect();
    assert_eq!(
        labels,
        [
            "hard",
            "adaptive:p_m=0",
            "adaptive:p_m=1000000",
            "regular:n=2",
            "regular:n=3"
        ]
    );
    // A threshold no quad reaches: the root quad's 4 corners only (method.md §3).
    assert_eq!(rows[2]["maps"], 4);
    assert!(
        out.join("charts/maps_vs_pm.svg").is_file(),
        "two P_M values: the maps-against-P_M chart is drawn"
    );
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert_self_contained(&html);
    assert!(html.contains("Shadow maps against P_M"));
}
