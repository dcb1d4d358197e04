//! `penumbra convergence` on a tiny scene: the rows, the fitted slope (a jittered grid converges
//! faster than the centred one), the output set, and its bad input.

#[macro_use]
mod common;
use common::{ok, penumbra, temp_dir};
use std::path::Path;

/// A box over a plane under a 2×2 light, 64² on screen; maps of 1024² so the sampling error, not
/// the map's own, dominates up to 256 maps.
fn scene(dir: &Path) -> String {
    let text = concat!(tiny_scene_head!(), "\n[[mesh]]\nbuiltin = \"plane\"\nscale = 10.0\n\n[[mesh]]\nbuiltin = \"box\"\ntranslate = [0.0, 1.0, 0.0]\n");
    let path = dir.join("tiny.toml");
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

fn study(scene: &str, method: &str, out: &Path) -> serde_json::Value {
    let args = [
        "convergence",
        "--scene",
        scene,
        "--method",
        method,
        "--set",
        "resolution=64",
        "--set",
        "shadow_map_size=1024",
        "--samples",
        "32",
        "--out",
        out.to_str().unwrap(),
    ];
    let stdout = String::from_utf8(ok(penumbra(&args), method).stdout).unwrap();
    println!("{stdout}");
    assert!(stdout.contains("| 16 | 256 |"), "{stdout}");
    serde_json::from_slice(&std::fs::read(out.join("convergence.json")).unwrap()).unwrap()
}

#[test]
fn error_falls_with_the_maps_and_jittered_falls_faster() {
    let dir = temp_dir("convergence_figures");
    let scene = scene(&dir);
    let centred = study(&scene, "regular:layout=centred", &dir.join("centred"));
    let jittered = study(&scene, "regular:layout=jittered", &dir.join("jittered"));
    for o in [&centred, &jittered] {
        let rows = o["rows"].as_array().unwrap();
        let maps: Vec<u64> = rows.iter().map(|r| r["maps"].as_u64().unwrap()).collect();
        assert_eq!(maps, [4, 9, 16, 36, 64, 121, 256], "{o}");
        let rmse: Vec<f64> = rows.iter().map(|r| r["rmse"].as_f64().unwrap()).collect();
        // Measured: 0.039 → 0.0025 (centred), 0.041 → 0.0009 (jittered).
        assert!(rmse[0] > 0.03 && rmse[0] < 0.05, "{rmse:?}");
        assert!(rmse[6] < rmse[0] / 10.0, "{rmse:?}");
    }
    let (c, j) = (
        centred["slope"].as_f64().unwrap(),
        jittered["slope"].as_f64().unwrap(),
    );
    // Measured: centred −0.58, jittered −0.84 (Monte Carlo alone would give −0.5).
    assert!((-0.75..-0.45).contains(&c), "centred slope {c}");
    assert!((-1.0..-0.7).contains(&j), "jittered slope {j}");
    // The CSV: a header and one row per value; the labels, which hold commas, quoted.
    let csv = std::fs::read_to_string(dir.join("jittered/convergence.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "scene,spec,method,params,maps,map_size,rmse,frame_ms,adapter,version,target,value,label,mae");
    assert_eq!(lines.len(), 8, "{csv}");
    assert!(
        lines[7].contains(",regular,") && lines[7].contains(",256,"),
        "{csv}"
    );
    assert!(
        lines[7].contains(",16,\"regular:n=16,layout=jittered\","),
        "{csv}"
    );
    let md = std::fs::read_to_string(dir.join("jittered/convergence.md")).unwrap();
    assert!(
        md.contains(&format!(
            "Fitted slope of log RMSE against log maps: {j:.3}"
        )),
        "{md}"
    );
}

#[test]
fn bad_input_is_one_line_and_writes_nothing() {
    let dir = temp_dir("convergence_bad_input");
    let scene = scene(&dir);
    let file = dir.join("a_file");
    std::fs::write(&file, "x").unwrap();
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let cases: [(Vec<&str>, String); 8] = [
        (vec!["--values", "4"], "--values 4: give at least two values to fit a slope".into()),
        (vec!["--method", "nosuch"], "--method nosuch: unknown method `nosuch` (known: hard, pcf,".into()),
        (vec!["--key", "taps"], "--key taps: not a parameter of method regular (`penumbra methods` lists them)".into()),
        (vec!["--method", "regular:n=4"], "--method regular:n=4: sets n itself; leave it to --values".into()),
        (vec!["--values", "2,4,02"], "--values `02`: listed twice (as `2`)".into()),
        (vec!["--values", "2,0"], "--values 0: regular: n = 0 is outside 1..=128".into()),
        (vec!["--set", "p_m=3"], "--set p_m=3: p_m is a parameter of methods adaptive, env-adaptive, not a render setting; write it in the method spec (adaptive:p_m=3)".into()),
        (vec!["--out", file.to_str().unwrap()], format!("--out {}: is a file, not a folder: give a folder for the output set", file.display())),
    ];
    for (extra, want) in cases {
        let mut args = vec!["convergence", "--scene", &scene];
        if !extra.contains(&"--out") {
            args.extend(["--out", o]);
        }
        args.extend(&extra);
        let r = penumbra(&args);
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{extra:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{extra:?}: {stderr}");
        assert!(
            stderr.starts_with(&format!("error: {want}")),
            "{extra:?}: {stderr}"
        );
        assert!(!out.exists(), "{extra:?} wrote {}", out.display());
    }
}

/// A value that fails at run time (here an item list held at 1 item, which overflows) is a row
/// saying why, with a warning naming `--values` and the value; the other values are measured and
/// the set is written. Before, the whole study was lost with an error naming neither.
#[test]
fn a_value_that_fails_at_run_time_is_a_row_and_the_study_goes_on() {
    let dir = temp_dir("convergence_failed_value");
    let scene = scene(&dir);
    let out = dir.join("out");
    let args = [
        "convergence",
        "--scene",
        &scene,
        "--method",
        "adaptive:scope=local,items_grow=off",
        "--key",
        "items",
        "--values",
        "1,4000000",
        "--set",
        "resolution=32",
        "--samples",
        "4",
        "--out",
        out.to_str().unwrap(),
    ];
    let r = penumbra(&args);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(r.status.success(), "{stderr}");
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .collect();
    assert_eq!(warnings.len(), 2, "{stderr}");
    assert!(
        warnings[0].starts_with("warning: --values 1 (adaptive:")
            && warnings[0].contains(": failed: overflow: adaptive level"),
        "{stderr}"
    );
    assert_eq!(
        warnings[1],
        "warning: 1 of 2 settings failed; their rows say why (\"failed\" in the results)"
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("convergence.json")).unwrap()).unwrap();
    let rows = json["rows"].as_array().unwrap();
    assert!(
        rows[0]["failed"]
            .as_str()
            .unwrap()
            .starts_with("overflow: "),
        "{json}"
    );
    assert!(
        rows[1].get("failed").is_none() && rows[1]["rmse"].as_f64().unwrap() > 0.0,
        "{json}"
    );
    let csv = std::fs::read_to_string(out.join("convergence.csv")).unwrap();
    assert!(
        csv.starts_with("scene,spec,method,params,maps,map_size,rmse,frame_ms,adapter,version,target,value,label,mae,failed\n")
            && csv.contains(",,,")
            && csv.contains("overflow: "),
        "{csv}"
    );
    assert!(std::fs::read_to_string(out.join("convergence.md"))
        .unwrap()
        .contains("| 1 | failed: overflow: "));
}
