//! `--certify K` (docs/certify.md): the certified bound in `render`'s run.json, in `compare`'s rows
//! and report and in `frontier`'s table; the bad inputs refused in one line with nothing written;
//! `penumbra certify-study` and `penumbra certify-promise` on small stand-ins of the committed runs;
//! and `penumbra reference --tracer gpu` equal to the CPU tracer's, bit for bit.

mod common;
use common::{ok, penumbra, temp_dir};

fn json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(
        &std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())),
    )
    .unwrap()
}

#[test]
fn render_certifies_its_frame_in_run_json() {
    let out = temp_dir("certify_render").join("out");
    let o = ok(
        penumbra(&[
            "render",
            "--scene",
            "analytic-square",
            "--set",
            "resolution=64",
            "--method",
            "pcss",
            "--certify",
            "1024",
            "--out",
            out.to_str().unwrap(),
        ]),
        "render --certify",
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    let c = &json(&out.join("run.json"))["certify"];
    let (bound, sampled) = (
        c["bound"].as_f64().unwrap(),
        c["sampled_rmse"].as_f64().unwrap(),
    );
    assert!(
        stdout.contains(&format!("certified: RMSE ≤ {bound:.4} at 95% (1024 px,")),
        "{stdout}"
    );
    assert_eq!(
        (
            c["pixels"].as_u64(),
            c["delta"].as_f64(),
            c["bound_kind"].as_str(),
            c["proxy"].as_str()
        ),
        (
            Some(1024),
            Some(0.05),
            Some("calibrated"),
            Some("second-opinion")
        ),
        "{c}"
    );
    assert!(
        sampled > 0.0
            && bound > sampled
            && c["per_frame_bound"].as_f64().unwrap() >= c["student_t_bound"].as_f64().unwrap(),
        "{c}"
    );
    // The exact pixels: 1024 rays a pixel at most, none decided by a tie.
    let unique = c["unique_pixels"].as_u64().unwrap();
    assert!(unique > 300 && unique <= 1024, "{c}");
    assert!(
        c["trace"]["rays"].as_u64().unwrap() <= unique * 1024 && c["trace"]["ties"] == 0,
        "{c}"
    );
    assert!(
        c["pixels_ms"].as_f64().unwrap() > 0.0 && c["bvh_ms"].as_f64().unwrap() > 0.0,
        "{c}"
    );
}

/// A scene lit by a 16x8 panorama, in `dir`.
fn environment_scene(dir: &std::path::Path) -> std::path::PathBuf {
    image::Rgb32FImage::from_fn(16, 8, |_, y| image::Rgb([if y < 4 { 1.0 } else { 0.1 }; 3]))
        .save_with_format(dir.join("sky.exr"), image::ImageFormat::OpenExr)
        .unwrap();
    let path = dir.join("env.toml");
    std::fs::write(&path, "name = \"env\"\n[camera]\neye = [0.0, 5.0, 8.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 45.0\n[environment]\npanorama = \"sky.exr\"\n[render]\nwidth = 32\nheight = 32\n[[mesh]]\nbuiltin = \"plane\"\nscale = [8.0, 1.0, 8.0]\n").unwrap();
    path
}

#[test]
fn bad_certify_inputs_are_refused_in_one_line_and_nothing_is_written() {
    let dir = temp_dir("certify_bad");
    let env = environment_scene(&dir);
    let env = env.to_str().unwrap();
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let square = ["--scene", "analytic-square", "--set", "resolution=32"];
    let cases: Vec<(Vec<&str>, String)> = vec![
        (
            [&["render"], &square[..], &["--certify", "0"]].concat(),
            "--certify 0: draw at least one pixel".into(),
        ),
        (
            [&["render"], &square[..], &["--certify", "1025"]].concat(),
            "--certify 1025: more than the frame's 1024 pixels (32x32)".into(),
        ),
        // Within the frame but over its geometry pixels: the frame says so before anything is written.
        (
            [&["render"], &square[..], &["--certify", "1000"]].concat(),
            "--certify 1000: more than the frame's".into(),
        ),
        (
            [
                &["render"],
                &square[..],
                &["--certify", "64", "--delta", "1.5"],
            ]
            .concat(),
            "--delta 1.5: outside (0, 1)".into(),
        ),
        (
            [
                &["render"],
                &square[..],
                &["--certify", "64", "--delta", "0"],
            ]
            .concat(),
            "--delta 0: outside (0, 1)".into(),
        ),
        (
            [&["render"], &square[..], &["--delta", "0.1"]].concat(),
            "--delta 0.1: needs --certify K".into(),
        ),
        (
            vec![
                "render",
                "--scene",
                env,
                "--method",
                "env-pixels",
                "--certify",
                "64",
            ],
            "an environment scene is lit by a panorama".into(),
        ),
        (
            [
                &["compare"],
                &square[..],
                &["--methods", "hard", "--certify", "0"],
            ]
            .concat(),
            "--certify 0: draw at least one pixel".into(),
        ),
        (
            [
                &["frontier"],
                &square[..],
                &["--certify", "64", "--delta", "2"],
            ]
            .concat(),
            "--delta 2: outside (0, 1)".into(),
        ),
        (
            vec!["certify-study", "--scenes", env],
            "an environment scene is lit by a panorama".into(),
        ),
    ];
    for (args, says) in cases {
        let args: Vec<&str> = args.into_iter().chain(["--out", o]).collect();
        let run = penumbra(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        let errors: Vec<&str> = stderr
            .lines()
            .filter(|l| l.starts_with("error: "))
            .collect();
        assert_eq!(run.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            errors.len() == 1 && errors[0].contains(&says),
            "{args:?}: expected `{says}`, got {stderr}"
        );
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
}

#[test]
fn compare_and_frontier_certify_every_setting() {
    let dir = temp_dir("certify_compare");
    let out = dir.join("compare");
    let o = ok(
        penumbra(&[
            "compare",
            "--scene",
            "analytic-square",
            "--set",
            "resolution=64",
            "--methods",
            "hard,pcss",
            "--repeats",
            "1",
            "--certify",
            "512",
            "--out",
            out.to_str().unwrap(),
        ]),
        "compare --certify",
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    let rows: Vec<serde_json::Value> = std::fs::read_to_string(out.join("results.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(rows.len(), 2);
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    for r in &rows {
        let c = &r["certify"];
        let (bound, rmse) = (
            c["bound"].as_f64().unwrap(),
            r["metrics"]["rmse"].as_f64().unwrap(),
        );
        let line = format!(
            "RMSE ≤ {bound:.4} at 95% (512 px, {:.0} ms)",
            c["pixels_ms"].as_f64().unwrap()
        );
        assert!(
            stdout.contains(&format!(
                "certified: {}: {line} (measured {rmse:.4})",
                r["label"].as_str().unwrap()
            )),
            "{stdout}"
        );
        assert!(md.contains(&line), "{md}");
        // The exact pixels and the second opinion are the same for both: the bound follows the error.
        assert!(
            bound > 0.0 && c["sampled_rmse"].as_f64().unwrap() > 0.0,
            "{r}"
        );
    }
    assert!(
        rows[0]["certify"]["bound"].as_f64().unwrap()
            > rows[1]["certify"]["bound"].as_f64().unwrap(),
        "hard errs more than pcss"
    );
    assert!(
        json(&out.join("images/hard/run.json"))["certify"]["trace"]["rays"]
            .as_u64()
            .unwrap()
            > 0
    );

    let out = dir.join("frontier");
    ok(
        penumbra(&[
            "frontier",
            "--scene",
            "analytic-square",
            "--set",
            "resolution=64",
            "--n",
            "2",
            "--sizes",
            "256",
            "--hybrid",
            "none",
            "--repeats",
            "1",
            "--certify",
            "256",
            "--out",
            out.to_str().unwrap(),
        ]),
        "frontier --certify",
    );
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(out.join("frontier.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let certified: Vec<&serde_json::Value> = lines
        .iter()
        .filter(|l| l["certify"]["bound"].is_number())
        .collect();
    assert!(
        certified.len() == lines.iter().filter(|l| l["failed"].is_null()).count()
            && certified.len() >= 4,
        "{lines:?}"
    );
    let md = std::fs::read_to_string(out.join("frontier.md")).unwrap();
    assert!(
        md.contains("## Certified error") && md.contains("at 95% (256 px,"),
        "{md}"
    );
}

#[test]
fn the_study_writes_every_draw_and_fits_the_stretch_on_the_fitting_half() {
    let out = temp_dir("certify_study").join("out");
    ok(
        penumbra(&[
            "certify-study",
            "--scenes",
            "analytic-square,disk-bar",
            "--set",
            "resolution=64",
            "--methods",
            "hard,pcss",
            "--pixels",
            "256,512",
            "--draws",
            "2",
            "--out",
            out.to_str().unwrap(),
        ]),
        "certify-study",
    );
    let rows = penumbra_lab::studies::certify::parse_csv(
        &std::fs::read_to_string(out.join("certify.csv")).unwrap(),
    )
    .unwrap();
    // analytic-square fits, disk-bar checks; hard and pcss, 2 proxies × 2 K × 2 draws each.
    let on = |scene: &str| rows.iter().filter(|r| r.core.scene == scene).count();
    assert_eq!(
        (on("analytic-square"), on("disk-bar")),
        (16, 16),
        "{rows:?}"
    );
    assert!(
        rows.iter()
            .all(|r| r.core.rmse > 0.0 && r.t_bound > 0.0 && r.per_frame_bound >= r.t_bound),
        "{rows:?}"
    );
    assert_eq!(rows.iter().filter(|r| r.half == "fitting").count(), 16);
    // Each row carries the core: the method by its label and name, one map at the scenes' 512²,
    // the frame's wall clock, the adapter and the build.
    assert!(
        rows.iter()
            .all(|r| ["hard", "pcss"].contains(&r.core.spec.as_str())
                && r.core.method == r.core.spec
                && (r.core.maps, r.core.map_size) == (1, 512)
                && r.core.frame_ms > 0.0
                && r.core.adapter.is_string()
                && r.core.version.is_string()),
        "{rows:?}"
    );
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        md.contains("| fitting | band | 512 | calibrated (t × ")
            && md.contains("| checking + held out | second-opinion | 256 | per-frame |"),
        "{md}"
    );
    assert!(
        md.contains("Stretch fitted on the fitting half at K = 2048"),
        "{md}"
    );
}

#[test]
fn the_promise_retake_renders_auto_beside_its_standing_oracle() {
    let dir = temp_dir("certify_promise");
    let frontier = dir.join("analytic-square");
    ok(
        penumbra(&[
            "frontier",
            "--scene",
            "analytic-square",
            "--set",
            "resolution=64",
            "--n",
            "2,3",
            "--sizes",
            "512",
            "--hybrid",
            "none",
            "--repeats",
            "1",
            "--budget",
            "0.05",
            "--out",
            frontier.to_str().unwrap(),
        ]),
        "frontier --budget",
    );
    let out = dir.join("promise");
    let o = ok(
        penumbra(&[
            "certify-promise",
            "--frontiers",
            frontier.to_str().unwrap(),
            "--repeats",
            "1",
            "--out",
            out.to_str().unwrap(),
        ]),
        "certify-promise",
    );
    let rows = penumbra_lab::studies::certify::promise::parse_csv(
        &std::fs::read_to_string(out.join("promise.csv")).unwrap(),
    )
    .unwrap();
    assert_eq!(rows.len(), 1, "{rows:?}");
    let r = &rows[0];
    assert_eq!(
        (r.core.scene.as_str(), r.target(), r.half.as_str()),
        ("analytic-square", 0.05, "fitting")
    );
    // The core is auto's row as compare measured it.
    assert_eq!(
        (r.core.spec.as_str(), r.core.method.as_str(), r.core.target),
        ("auto:target=0.05", "auto", Some(0.05)),
        "{r:?}"
    );
    assert!(
        r.core.maps >= 1 && r.core.map_size >= 512 && r.core.version.is_string(),
        "{r:?}"
    );
    // The oracle rendered again beside auto reads the frontier's RMSE, bit for bit.
    assert!(
        r.oracle.is_some() && r.oracle_rmse == r.frontier_oracle_rmse,
        "{r:?}"
    );
    assert_eq!(
        r.time_over_oracle,
        Some(r.core.frame_ms / r.oracle_ms.unwrap())
    );
    assert_eq!(r.target_met, r.bound <= 0.05, "{r:?}");
    assert!(
        r.tests >= 1 && r.decision_ms > 0.0 && r.bound_kind == "calibrated",
        "{r:?}"
    );
    let md = String::from_utf8_lossy(&o.stdout);
    assert!(
        md.contains("| measured RMSE ≤ T, all rows | ")
            && md.contains("| analytic-square | fitting | 0.05 | "),
        "{md}"
    );
}

#[test]
fn the_gpu_tracer_traces_the_whole_reference_as_the_cpu_does() {
    let dir = temp_dir("certify_reference");
    for scene in ["default", "spot-edge"] {
        let read = |tracer: &str| {
            let out = dir.join(format!("{scene}-{tracer}"));
            let o = ok(
                penumbra(&[
                    "reference",
                    "--scene",
                    scene,
                    "--set",
                    "resolution=48",
                    "--no-cache",
                    "--tracer",
                    tracer,
                    "--out",
                    out.to_str().unwrap(),
                ]),
                "reference --tracer",
            );
            (
                std::fs::read(out.join("reference.exr")).unwrap(),
                json(&out.join("reference.json")),
                String::from_utf8_lossy(&o.stdout).to_string(),
            )
        };
        let (cpu, cpu_record, _) = read("cpu");
        let (gpu, gpu_record, line) = read("gpu");
        assert!(
            cpu == gpu,
            "{scene}: the GPU's reference differs from the CPU's"
        );
        assert_eq!(
            (
                cpu_record["trace"]["tracer"].as_str(),
                gpu_record["trace"]["tracer"].as_str()
            ),
            (Some("cpu"), Some("gpu"))
        );
        assert_eq!(gpu_record["trace"]["ties"], 0, "{gpu_record}");
        assert_eq!(
            cpu_record["key"], gpu_record["key"],
            "one cache key whoever traces"
        );
        assert!(line.contains("traced on the GPU in"), "{line}");
    }
    let o = penumbra(&[
        "reference",
        "--scene",
        "point-edge",
        "--set",
        "resolution=32",
        "--mode",
        "lattice",
        "--tracer",
        "gpu",
        "--out",
        dir.join("x").to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.code() == Some(1) && stderr.contains("--tracer gpu: builtin:point-edge: the lattice and point modes of a point or spot light"), "{stderr}");
}
