//! `penumbra estimate` (docs/error-estimate.md §5): the documented small run writes its set, every
//! line's ratio and verdict follow from its own figures, and bad input is refused before anything
//! is written.

mod common;

#[test]
fn estimate_study_writes_its_set() {
    let out = common::temp_dir("estimate-study").join("out");
    let o = common::penumbra(&[
        "estimate",
        "--scenes",
        "overlapping-occluders,disk-bar",
        "--set",
        "resolution=64",
        "--settings",
        "regular:n=3,layout=centred@256;regular:n=4,layout=jittered@512",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        stdout.contains("predicted/measured RMSE in [0.8, 1.25]"),
        "{stdout}"
    );
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(out.join("estimate.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 4, "two scenes × two settings");
    for l in &lines {
        let (m, p) = (
            l["rmse"].as_f64().unwrap(),
            l["predicted_rmse"].as_f64().unwrap(),
        );
        assert!(m > 0.0 && p > 0.0, "{l}");
        assert!((l["ratio"].as_f64().unwrap() - p / m).abs() < 1e-9, "{l}");
        assert_eq!(
            l["within"].as_bool().unwrap(),
            (0.8..=1.25).contains(&(p / m)),
            "{l}"
        );
        let (s, mp) = (
            l["predicted_sampling"].as_f64().unwrap(),
            l["predicted_map"].as_f64().unwrap(),
        );
        assert!((p - (s * s + mp * mp).sqrt()).abs() < 1e-9, "{l}");
        let cover = l["bound_coverage"].as_f64().unwrap();
        assert!(cover > 0.5 && cover <= 1.0, "{l}");
        // The measured split: the maps' error and the sampling error both exist on these scenes.
        assert!(
            l["measured_map"].as_f64().unwrap() > 0.0
                && l["measured_sampling"].as_f64().unwrap() > 0.0,
            "{l}"
        );
        assert!(l["exact"].as_str().unwrap().starts_with("mean of"), "{l}");
    }
    let md = std::fs::read_to_string(out.join("estimate.md")).unwrap();
    assert!(
        md.contains("| overlapping-occluders | n=3 centred @256 |"),
        "{md}"
    );
    // Which part limits the count: recomputed from the lines' own figures.
    let f = |l: &serde_json::Value, k: &str| l[k].as_f64().unwrap();
    let band = |x: f64, y: f64| (0.8..=1.25).contains(&(x / y));
    let count = |g: &dyn Fn(&serde_json::Value) -> bool| lines.iter().filter(|l| g(l)).count();
    let parts = (
        count(&|l| band(f(l, "predicted_sampling"), f(l, "measured_sampling"))),
        count(&|l| band(f(l, "predicted_map"), f(l, "measured_map"))),
    );
    let swapped = (
        count(&|l| {
            band(
                f(l, "measured_sampling").hypot(f(l, "predicted_map")),
                f(l, "rmse"),
            )
        }),
        count(&|l| {
            band(
                f(l, "predicted_sampling").hypot(f(l, "measured_map")),
                f(l, "rmse"),
            )
        }),
        count(&|l| {
            band(
                f(l, "measured_sampling").hypot(f(l, "measured_map")),
                f(l, "rmse"),
            )
        }),
    );
    let expect = format!(
        "the sampling part's own ratio is in the band on {} pairs and the maps' on {}; with the measured sampling error in place of its prediction, the total is in the band on {}, with the measured maps' error on {}, with both (the measured parts' squares added) on {}.",
        parts.0, parts.1, swapped.0, swapped.1, swapped.2
    );
    assert!(
        md.contains(&expect) && stdout.contains(&expect),
        "{expect}\n{md}"
    );
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(
        html.contains("src=\"data:image/svg+xml;base64,") && !html.contains("http://"),
        "the chart is a data URI, and nothing is named by address"
    );
    assert!(
        !html.contains("src=\"http") && !html.contains("<script"),
        "self-contained"
    );
    for f in ["charts/estimate.svg", "charts/estimate.png"] {
        assert!(out.join(f).is_file(), "{f}");
    }
}

#[test]
fn estimate_study_refuses_bad_input() {
    let out = common::temp_dir("estimate-study-bad").join("out");
    let o = out.to_str().unwrap();
    for (args, expect) in [
        (
            vec!["--settings", "regular:n=3@huge"],
            "--settings `regular:n=3@huge`",
        ),
        (vec!["--settings", "hard@512"], "built for `regular` grids"),
        (vec!["--scenes", "no-such-scene"], "no-such-scene"),
        (
            vec!["--set", "shadow_map_size=256"],
            "each setting names its map size",
        ),
        (vec!["--samples", "0"], "--samples must be in 1..=256"),
    ] {
        let mut a = vec![
            "estimate",
            "--scenes",
            "disk-bar",
            "--set",
            "resolution=32",
            "--out",
            o,
        ];
        a.extend(args.iter().copied());
        let r = common::penumbra(&a);
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(expect), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?}: nothing written");
    }
}
