//! `penumbra calibrate` (docs/budget.md) on pairs written here: each pair's half from the fixed
//! split, its class from its scene's light, the engine's factors read by half, and bad input
//! refused with one line and no output.

mod common;
use common::{ok, penumbra, temp_dir};
use penumbra::research::methods::calibration::{CUBE, PLANE};

/// One `estimate.jsonl` line: only the figures the calibration reads are set.
fn line(scene: &str, measured: f64, sampling: f64, map: f64) -> String {
    serde_json::json!({
        "scene": scene, "spec": "regular:n=5,layout=centred", "layout": "centred", "map_size": 512, "maps": 25,
        "measured_rmse": measured, "predicted_rmse": sampling.hypot(map), "predicted_sampling": sampling, "predicted_map": map,
        "ratio": sampling.hypot(map) / measured, "within": true, "bound_coverage": 1.0, "measured_map": map, "measured_sampling": sampling,
        "exact": "mean of 25 point references", "resolution": [128, 128], "reference": "continuous 32x32", "adapter": "test"
    })
    .to_string()
}

#[test]
fn calibrate_reads_the_engines_factors_by_half() {
    let dir = temp_dir("calibrate");
    // default fits, slat-roof checks (built in, its meshes inline: no asset cache is read),
    // point-room (a ball light) checks: the ball light's sampling factor is CUBE's, decided from
    // its light.
    let lines = [
        line("default", 0.02, 0.01, 0.01),
        line("slat-roof", 0.02, 0.012, 0.012),
        line("point-room", 0.02, 0.012, 0.0),
    ]
    .join("\n");
    let file = dir.join("estimate.jsonl");
    std::fs::write(&file, lines + "\n").unwrap();
    let out = dir.join("out");
    let o = ok(
        penumbra(&[
            "calibrate",
            "--estimates",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]),
        "calibrate",
    );
    let md = String::from_utf8_lossy(&o.stdout);
    let cal = |s: f64, m: f64, f: penumbra::research::methods::calibration::Factors| {
        (f.sampling * s).hypot(f.map * m)
    };
    let (d, t, p) = (
        cal(0.01, 0.01, PLANE),
        cal(0.012, 0.012, PLANE),
        cal(0.012, 0.0, CUBE),
    );
    assert!(
        md.contains(&format!(
            "| fitting | 1 | {} | {:.1}% | {:.2} |",
            usize::from(d >= 0.02),
            if d >= 0.02 { 100.0 } else { 0.0 },
            d / 0.02
        )),
        "{md}"
    );
    let covered = usize::from(t >= 0.02) + usize::from(p >= 0.02);
    let mut ratios = [t / 0.02, p / 0.02];
    ratios.sort_by(f64::total_cmp);
    assert!(
        md.contains(&format!(
            "| checking | 2 | {covered} | {:.1}% | {:.2} |",
            50.0 * covered as f64,
            0.5 * (ratios[0] + ratios[1])
        )),
        "{md}"
    );
    let csv = std::fs::read_to_string(out.join("pairs.csv")).unwrap();
    assert!(
        csv.lines()
            .nth(3)
            .unwrap()
            .starts_with("point-room,checking,cube,"),
        "{csv}"
    );
    assert!(out.join("charts/calibration.svg").is_file() && out.join("charts/parts.svg").is_file());
}

#[test]
fn calibrate_refuses_bad_input_with_one_line_and_no_output() {
    let dir = temp_dir("calibrate_bad");
    let file = dir.join("estimate.jsonl");
    std::fs::write(&file, line("not-a-scene", 0.02, 0.01, 0.01) + "\n").unwrap();
    let missing = dir.join("missing.jsonl");
    let out = dir.join("out");
    for (args, want) in [
        (vec!["--estimates", missing.to_str().unwrap()], format!("error: --estimates {}: cannot read", missing.display())),
        (vec!["--estimates", file.to_str().unwrap()], format!("error: --estimates {}: line 1: scene `not-a-scene` is not built in; name its TOML in --scenes", file.display())),
    ] {
        let mut all = vec!["calibrate"];
        all.extend(args);
        all.extend(["--out", out.to_str().unwrap()]);
        let o = penumbra(&all);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.starts_with(&want), "{want}\n{stderr}");
        assert!(!out.exists(), "nothing written");
    }
}
