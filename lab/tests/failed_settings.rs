//! A setting that fails at run time is a failed row with its reason, and the study goes on
//! (robustness.md, "Failed settings"): in `compare`, `sweep`, `frontier`, `estimate` and `bench`,
//! each with one forced failure, the run exits 0, writes its whole set, warns once on stderr, and
//! the other settings' rows are there. The forced failure is deterministic: scope = local's item
//! list held at 100 items (`items=100,items_grow=off`, or `PENUMBRA_ITEMS_FIXED=100` where the
//! settings come from a grid), or a map larger than the map budget.

#[macro_use]
mod common;
use common::{penumbra_env, temp_dir};
use penumbra_lab::studies::frontier::{mark, FrontierLine};
use std::path::Path;

/// The overflow at level 0 of slat-roof at 32²: its 844 geometry pixels do not fit 100 items.
const OVERFLOW: &str = "overflow: adaptive level 0: the (pixel, quad) item list exceeded its capacity (flags 0x2); the run is not valid";

fn jsonl(path: &Path) -> Vec<serde_json::Value> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The run succeeded and warned once for `label`, with the closing count `failed of total`.
fn finished_with_one_failure(o: &std::process::Output, label: &str, reason: &str, total: usize) {
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{stderr}");
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("warning: "))
        .collect();
    assert_eq!(
        warnings,
        [format!("warning: {label}: failed: {reason}"), format!("warning: 1 of {total} settings failed; their rows say why (\"failed\" in the results)")],
        "{stderr}"
    );
}

/// Runs with a reference cache of the test's own: the warnings are compared line for line, and a
/// shared cache may hold an entry an older build wrote, which is traced again with a warning.
fn private_cache(dir: &Path, args: &[&str]) -> std::process::Output {
    penumbra_env(
        args,
        &[("PENUMBRA_CACHE", dir.join("cache").to_str().unwrap())],
    )
}

/// compare's and sweep's output set: the failed row with its reason, the others measured.
fn check_compare_set(out: &Path, failed_label: &str, measured: &[&str]) {
    let rows = jsonl(&out.join("results.jsonl"));
    assert_eq!(rows.len(), measured.len() + 1);
    let failed: Vec<&serde_json::Value> =
        rows.iter().filter(|r| r.get("failed").is_some()).collect();
    assert_eq!(failed.len(), 1, "{rows:?}");
    assert_eq!(
        (failed[0]["label"].as_str(), failed[0]["failed"].as_str()),
        (Some(failed_label), Some(OVERFLOW))
    );
    for label in measured {
        let r = rows
            .iter()
            .find(|r| r["label"] == *label)
            .unwrap_or_else(|| panic!("{label} missing"));
        assert!(
            r["metrics"]["rmse"].as_f64().unwrap() > 0.0 && r["maps"].as_u64().unwrap() >= 1,
            "{r}"
        );
        assert!(out
            .join(r["images"]["visibility"].as_str().unwrap())
            .exists());
    }
    let csv = read(&out.join("results.csv"));
    assert!(csv.lines().next().unwrap().ends_with(",failed"), "{csv}");
    let line = csv.lines().find(|l| l.contains(failed_label)).unwrap();
    // The reason holds a comma: quoted. The figures between the map size and the reference (20
    // cells) are empty; the adapter and the map size stay.
    assert!(line.ends_with(&format!(",\"{OVERFLOW}\"")), "{line}");
    let figures = format!(",{},continuous 32x32,", ",".repeat(19));
    let (before, _) = line
        .split_once(&figures)
        .unwrap_or_else(|| panic!("{line}"));
    assert!(
        before.rsplit(',').next().unwrap().parse::<u32>().is_ok(),
        "{line}"
    );
    let md = read(&out.join("report.md"));
    assert!(
        md.contains(&format!("| {failed_label} | failed: {OVERFLOW} |")),
        "{md}"
    );
    for f in ["report.html", "reference.exr", "charts/error_vs_time.svg"] {
        assert!(out.join(f).exists(), "{f}");
    }
}

#[test]
fn compare_records_a_failed_method_and_goes_on() {
    let dir = temp_dir("failed-compare");
    let out = dir.join("out");
    let label = "adaptive:p_m=0,scope=local,items=100,items_grow=off";
    let o = private_cache(
        &dir,
        &[
            "compare",
            "--scene",
            "slat-roof",
            "--set",
            "resolution=32",
            "--repeats",
            "1",
            "--methods",
            "hard,adaptive:scope=local,items=100,items_grow=off,regular:n=2",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    finished_with_one_failure(&o, label, OVERFLOW, 3);
    check_compare_set(&out, label, &["hard", "regular:n=2"]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout
            .lines()
            .any(|l| l.starts_with(label) && l.ends_with(&format!("  failed: {OVERFLOW}"))),
        "{stdout}"
    );
}

#[test]
fn sweep_records_a_failed_configuration_and_goes_on() {
    let dir = temp_dir("failed-sweep");
    let spec = dir.join("spec.toml");
    std::fs::write(&spec, "methods = [\"hard\"]\n[[grid]]\nmethod = \"adaptive\"\nscope = \"local\"\nitems_grow = \"off\"\nitems = [100, 100000]\n").unwrap();
    let out = dir.join("out");
    let o = private_cache(
        &dir,
        &[
            "sweep",
            "--spec",
            spec.to_str().unwrap(),
            "--scene",
            "slat-roof",
            "--set",
            "resolution=32",
            "--repeats",
            "1",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let label = "adaptive:p_m=0,scope=local,items=100,items_grow=off";
    finished_with_one_failure(&o, label, OVERFLOW, 3);
    check_compare_set(
        &out,
        label,
        &[
            "hard",
            "adaptive:p_m=0,scope=local,items=100000,items_grow=off",
        ],
    );
}

#[test]
fn frontier_records_failed_settings_and_keeps_them_off_the_front() {
    let out = temp_dir("failed-frontier").join("out");
    let o = penumbra_env(
        &[
            "frontier",
            "--scene",
            "slat-roof",
            "--set",
            "resolution=32",
            "--n",
            "2",
            "--sizes",
            "64",
            "--hybrid",
            "none",
            "--repeats",
            "1",
            "--budget",
            "0.2",
            "--out",
            out.to_str().unwrap(),
        ],
        &[("PENUMBRA_ITEMS_FIXED", "100")],
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{stderr}");
    // Both local settings of the grid overflow; the other 14 (auto and regions at the target among
    // them) are measured.
    let local = [
        "adaptive:preset=seed,scope=local,cull=on",
        "adaptive:preset=balanced,scope=local,cull=on",
    ];
    for spec in local {
        assert!(
            stderr
                .lines()
                .any(|l| l == format!("warning: {spec} @ plain 64: failed: {OVERFLOW}")),
            "{stderr}"
        );
    }
    assert!(
        stderr.lines().any(|l| l
            == "warning: 2 of 16 settings failed; their rows say why (\"failed\" in the results)"),
        "{stderr}"
    );
    let lines = jsonl(&out.join("frontier.jsonl"));
    assert_eq!(lines.len(), 16);
    for l in &lines {
        let failed = local.contains(&l["spec"].as_str().unwrap());
        assert_eq!(l["failed"].as_str(), failed.then_some(OVERFLOW), "{l}");
        if failed {
            assert_eq!(
                (
                    l["on_frontier"].as_bool(),
                    l["beaten_by"].as_str(),
                    l["oracle"].as_str()
                ),
                (Some(false), None, None),
                "{l}"
            );
        } else {
            assert!(l["rmse"].as_f64().unwrap() > 0.0, "{l}");
        }
    }
    // The budget row's oracle and rival are measured settings.
    let budget = lines.iter().find(|l| l["kind"] == "error budget").unwrap();
    for key in ["oracle", "beaten_by"] {
        if let Some(name) = budget[key].as_str() {
            assert!(!local.iter().any(|s| name.starts_with(s)), "{key}: {name}");
        }
    }
    let md = read(&out.join("frontier.md"));
    assert!(
        md.contains(&format!(
            "| {} @ plain 64 | adaptive local | failed: {OVERFLOW} |",
            local[0]
        )),
        "{md}"
    );
    assert!(out.join("report.html").exists() && out.join("charts/frontier.svg").exists());
}

fn line(spec: &str, ms: f64, rmse: f64, kind: &str, failed: Option<&str>) -> FrontierLine {
    FrontierLine {
        core: penumbra_lab::record::RowCore {
            scene: "s".into(),
            spec: spec.into(),
            maps: 1,
            map_size: 64,
            rmse,
            frame_ms: ms,
            ..Default::default()
        },
        map_config: "plain 64".into(),
        kind: kind.into(),
        label: spec.into(),
        flip: None,
        frame_ms_min: ms,
        frame_ms_max: ms,
        on_frontier: false,
        beaten_by: None,
        thinning: String::new(),
        resolution: [32, 32],
        reference: String::new(),
        repeats: 1,
        clock: String::new(),
        raster: String::new(),
        oracle: None,
        budget: None,
        paired: None,
        second_look: None,
        failed: failed.map(String::from),
        certify: None,
    }
}

/// A failed line's zeros (0 ms, RMSE 0) would dominate every setting: the front, the rivals and
/// the budget's oracle must not see it.
#[test]
fn the_front_and_the_oracle_skip_failed_lines() {
    let mut lines = vec![
        line("regular:n=2", 2.0, 0.3, "regular lattice", None),
        line("regular:n=3", 5.0, 0.1, "regular lattice", None),
        line(
            "adaptive:scope=local",
            0.0,
            0.0,
            "adaptive local",
            Some("overflow: …"),
        ),
        line("auto:target=0.2", 3.0, 0.15, "error budget", None),
    ];
    mark(&mut lines);
    let on: Vec<bool> = lines.iter().map(|l| l.on_frontier).collect();
    assert_eq!(on, [true, true, false, false]);
    assert_eq!(
        (lines[2].beaten_by.as_deref(), lines[2].oracle.as_deref()),
        (None, None)
    );
    // The budget's oracle: the cheapest measured setting within 1.2 × 0.2; its rival: the cheapest at most its RMSE.
    assert_eq!(lines[3].oracle.as_deref(), Some("regular:n=3 @ plain 64"));
    assert_eq!(
        lines[3].beaten_by.as_deref(),
        Some("regular:n=3 @ plain 64")
    );
}

#[test]
fn estimate_records_a_failed_setting_and_goes_on() {
    let dir = temp_dir("failed-estimate");
    let out = dir.join("out");
    // A 1024² map (4 MiB) does not fit a 1 MiB map budget; the 256² one does.
    let o = private_cache(
        &dir,
        &[
            "estimate",
            "--scenes",
            "slat-roof",
            "--set",
            "resolution=32",
            "--set",
            "shadow_map_budget_mib=1",
            "--settings",
            "regular:n=2@256;regular:n=2@1024",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let reason = "one 1024x1024 shadow map (4 MiB) does not fit shadow_map_budget_mib = 1";
    finished_with_one_failure(&o, "slat-roof regular:n=2 @1024", reason, 2);
    let lines = jsonl(&out.join("estimate.jsonl"));
    assert_eq!(lines.len(), 2);
    assert_eq!(
        (lines[0].get("failed"), lines[0]["map_size"].as_u64()),
        (None, Some(256))
    );
    assert!(
        lines[0]["rmse"].as_f64().unwrap() > 0.0
            && lines[0]["predicted_rmse"].as_f64().unwrap() > 0.0
    );
    assert_eq!(
        (lines[1]["failed"].as_str(), lines[1]["map_size"].as_u64()),
        (Some(reason), Some(1024))
    );
    let md = read(&out.join("estimate.md"));
    assert!(
        md.contains(&format!("| slat-roof | n=2 @1024 | failed: {reason} |")),
        "{md}"
    );
    assert!(
        md.contains("1 of 2 settings failed")
            && md.contains("predicted/measured RMSE in [0.8, 1.25]: ")
            && md.contains(" of 1 pairs"),
        "{md}"
    );
    assert!(out.join("report.html").exists() && out.join("charts/estimate.svg").exists());
}

#[test]
fn bench_records_a_failed_method_and_goes_on() {
    let dir = temp_dir("failed-bench");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    let scene = concat!("triangles = 14\n", tiny_scene_head!(), "[[mesh]]\nbuiltin = \"plane\"\nscale = 10.0\n\n[[mesh]]\nbuiltin = \"box\"\ntranslate = [0.0, 1.0, 0.0]\n");
    std::fs::write(scenes.join("teapot.toml"), scene).unwrap();
    let out = dir.join("out");
    let label = "adaptive:p_m=0,scope=local,items=100,items_grow=off";
    let o = penumbra_env(
        &[
            "bench",
            "--suite",
            "seed-table2",
            "--repeats",
            "1",
            "--only",
            "teapot",
            "--scenes",
            scenes.to_str().unwrap(),
            "--adaptive",
            "adaptive:scope=local,items=100,items_grow=off",
            "--out",
            out.to_str().unwrap(),
        ],
        &[("PENUMBRA_CACHE", dir.join("cache").to_str().unwrap())],
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{stderr}");
    // 32² holds 1024 pixels, most of them ground: past 100 items at level 0. The probe frame fails
    // first (no fair grid without its map count), then the measured one.
    let overflow = OVERFLOW;
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("warning: "))
        .collect();
    assert_eq!(
        warnings,
        [
            format!("warning: teapot {label}: failed: {overflow}"),
            format!("warning: teapot {label}: failed: {overflow}"),
            "warning: 2 of 4 settings failed; their rows say why (\"failed\" in the results)"
                .to_string(),
        ],
        "{stderr}"
    );
    let rows = jsonl(&out.join("results.jsonl"));
    assert_eq!(rows.len(), 4, "adaptive, lattice, fair grid, per region");
    assert_eq!(rows[0]["failed"].as_str(), Some(overflow));
    // The per-region row comes after the failed fair grid, measured: a missing grid shifts nothing.
    assert_eq!(
        (rows[3]["method"].as_str(), rows[3].get("failed")),
        (Some("regions"), None)
    );
    assert!(
        rows[3]["metrics"]["rmse"].as_f64().unwrap() > 0.0,
        "{}",
        rows[3]
    );
    assert_eq!(
        (rows[1]["label"].as_str(), rows[1].get("failed")),
        (Some("regular:n=17"), None)
    );
    assert!(rows[1]["metrics"]["rmse"].as_f64().unwrap() > 0.0);
    assert_eq!(
        rows[2]["failed"].as_str(),
        Some(format!("no fair grid: the adaptive probe frame failed ({overflow})").as_str())
    );
    let table = read(&out.join("table2.md"));
    assert!(
        table.contains(&format!("| teapot | `{label}` | failed: {overflow} |")),
        "{table}"
    );
    assert!(
        table.contains("| teapot | `regular:n=17` | 289 |"),
        "{table}"
    );
    assert!(out.join("report.html").exists());
}
