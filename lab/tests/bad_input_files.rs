//! Input files that are not what they claim: a device or FIFO in place of a scene, rows file or
//! cache entry; rows whose figures cannot be (an RMSE of 1e308 or -0.5, a time of 1e308 ms); an
//! estimate file given twice or lying inside the set the run replaces; a results folder whose
//! README links out of the page. Each is one line naming the file or flag, the key and the value,
//! exit 1 and nothing written, or (a FIFO, a pipe, a cache entry) the run goes on and says so
//! (docs/robustness.md, "Bad input"). Everything here but the FIFO scene runs without a GPU.

mod common;
use common::temp_dir;
use std::path::Path;
use std::process::{Command, Output};

fn run_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .current_dir(dir)
        .args(args)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .env("PENUMBRA_CACHE", dir.join("cache"))
        .output()
        .unwrap()
}

/// The one error line (without `error: `) of a run that must refuse, after checking exit 1, no
/// panic and no `out` folder.
fn refused(dir: &Path, args: &[&str]) -> String {
    let o = run_in(dir, args);
    let e = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(1), "{args:?}: {e}");
    assert_eq!(e.lines().count(), 1, "{args:?}: {e}");
    assert!(!dir.join("out").exists(), "{args:?}: output written");
    e.trim().strip_prefix("error: ").unwrap_or(&e).to_string()
}

/// A good estimate row, with `changes` merged over it.
fn estimate_row(changes: serde_json::Value) -> String {
    let mut row = serde_json::json!({
        "scene": "analytic-square", "spec": "regular:n=3@64", "layout": "lattice", "map_size": 64, "maps": 9,
        "measured_rmse": 0.05, "predicted_rmse": 0.06, "predicted_sampling": 0.05, "predicted_map": 0.03,
        "ratio": 1.2, "within": true, "bound_coverage": 0.9, "measured_map": 0.02, "measured_sampling": 0.04,
        "exact": "lattice", "resolution": [64, 64], "reference": "continuous 8x8", "adapter": "x"
    });
    for (k, v) in changes.as_object().unwrap() {
        row[k] = v.clone();
    }
    row.to_string() + "\n"
}

#[test]
fn devices_in_place_of_input_files_are_refused_on_their_metadata() {
    let dir = temp_dir("bad_files_devices");
    std::os::unix::fs::symlink("/dev/zero", dir.join("z.toml")).unwrap();
    let e = refused(&dir, &["render", "--scene", "z.toml", "--out", "out"]);
    assert_eq!(e, "z.toml: cannot read: z.toml (a link to /dev/zero) is a character device, not a regular file or a pipe");
    let e = refused(
        &dir,
        &["calibrate", "--estimates", "/dev/zero", "--out", "out"],
    );
    assert_eq!(e, "--estimates /dev/zero: cannot read: /dev/zero is a character device, not a regular file or a pipe");
    std::fs::create_dir(dir.join("r")).unwrap();
    std::fs::write(dir.join("r/README.md"), "# r\n").unwrap();
    std::os::unix::fs::symlink("/dev/zero", dir.join("r/rows.csv")).unwrap();
    let e = refused(&dir, &["report", "r", "--out", "out"]);
    assert_eq!(e, "report: r/rows.csv: cannot read: r/rows.csv (a link to /dev/zero) is a character device, not a regular file or a pipe");
    std::os::unix::fs::symlink("/dev/zero", dir.join("results.jsonl")).unwrap();
    let e = refused(&dir, &["report", "results.jsonl", "--out", "out"]);
    assert!(e.ends_with("results.jsonl (a link to /dev/zero) is a character device, not a regular file or a pipe"), "{e}");
}

/// A FIFO with no writer: the run says what it waits for, and reads it once written; a pipe from
/// the shell (`--scene <(cat s.toml)`) works as before.
#[test]
fn a_scene_fifo_is_waited_for_with_a_word_and_a_pipe_works() {
    let _ = common::gpu();
    let dir = temp_dir("bad_files_fifo");
    let fifo = dir.join("f.toml");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let child = Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .current_dir(&dir)
        .args([
            "render",
            "--scene",
            "f.toml",
            "--set",
            "resolution=32",
            "--out",
            "out",
        ])
        .env("PENUMBRA_NO_PROGRESS", "1")
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(2500));
    // The writer comes late: the run has said that it waits, and goes on once it is written.
    std::fs::write(
        &fifo,
        std::fs::read_to_string(common::root().join("scenes/analytic-square.toml")).unwrap(),
    )
    .unwrap();
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("waiting for f.toml (a FIFO) to be written and closed; stop with Ctrl-C"),
        "{err}"
    );
    assert!(dir.join("out/run.json").is_file());
    std::fs::copy(
        common::root().join("scenes/analytic-square.toml"),
        dir.join("s.toml"),
    )
    .unwrap();
    let o = Command::new("bash")
        .current_dir(&dir)
        .args([
            "-c",
            &format!(
                "{} render --scene <(cat s.toml) --set resolution=32 --out piped",
                env!("CARGO_BIN_EXE_penumbra")
            ),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.join("piped/run.json").is_file());
}

#[test]
fn rows_read_back_are_checked_with_file_line_and_key() {
    let dir = temp_dir("bad_files_rows");
    let cases: [(&str, serde_json::Value, &str); 7] = [
        ("huge", serde_json::json!({"measured_rmse": 1e308}), "line 1: rmse = 1e308: an RMSE of V lies in (0, 1] (a pair with no error has no ratio to calibrate)"),
        ("zero", serde_json::json!({"measured_rmse": 0.0}), "line 1: rmse = 0: an RMSE of V lies in (0, 1]"),
        ("negative", serde_json::json!({"measured_rmse": -0.5}), "line 1: rmse = -0.5: an RMSE of V lies in (0, 1]"),
        ("sampling", serde_json::json!({"predicted_sampling": -1.0}), "line 1: predicted_sampling = -1: a predicted RMSE is a finite number, at least 0"),
        ("map", serde_json::json!({"measured_map": 1.5}), "line 1: measured_map = 1.5: an RMSE of V lies in [0, 1]"),
        ("size", serde_json::json!({"map_size": 0}), "line 1: map_size = 0, maps = 9: a setting has at least one map of at least one texel"),
        ("nothing", serde_json::json!({"predicted_sampling": 0.0, "predicted_map": 0.0}), "line 1: predicted_sampling = 0 and predicted_map = 0: a prediction of no error has nothing to calibrate"),
    ];
    for (name, changes, want) in cases {
        std::fs::write(dir.join(format!("{name}.jsonl")), estimate_row(changes)).unwrap();
        let e = refused(
            &dir,
            &[
                "calibrate",
                "--estimates",
                &format!("{name}.jsonl"),
                "--out",
                "out",
            ],
        );
        assert!(
            e.starts_with(&format!("--estimates {name}.jsonl: {want}")),
            "{name}: {e}"
        );
    }
    std::fs::write(dir.join("empty.jsonl"), "\n").unwrap();
    let e = refused(
        &dir,
        &["calibrate", "--estimates", "empty.jsonl", "--out", "out"],
    );
    assert_eq!(e, "--estimates empty.jsonl: holds no estimate row (give an estimate.jsonl of `penumbra estimate`)");
    std::fs::write(
        dir.join("failed.jsonl"),
        estimate_row(serde_json::json!({"failed": "out of memory", "measured_rmse": 0.0})),
    )
    .unwrap();
    let e = refused(
        &dir,
        &["calibrate", "--estimates", "failed.jsonl", "--out", "out"],
    );
    assert_eq!(
        e,
        "--estimates failed.jsonl: all 1 rows are failed settings: no pair to calibrate"
    );
    std::fs::write(dir.join("good.jsonl"), estimate_row(serde_json::json!({}))).unwrap();
    let e = refused(
        &dir,
        &[
            "calibrate",
            "--estimates",
            "good.jsonl,./good.jsonl",
            "--out",
            "out",
        ],
    );
    assert_eq!(
        e,
        "--estimates `./good.jsonl`: listed twice (as `good.jsonl`)"
    );
}

/// `report` on rows whose figures cannot be: refused at the file and line, where an RMSE of 1e308
/// once made the chart's log axis walk two billion decades (2.6 GB in 40 s).
#[test]
fn report_refuses_result_rows_whose_figures_cannot_be() {
    let dir = temp_dir("bad_files_report_rows");
    let row = |changes: serde_json::Value| {
        let mut r = serde_json::json!({
            "scene": "s", "method": "hard", "params": {}, "adapter": "a", "maps": 1, "rmse": 0.1, "frame_ms": 2.0, "frame_ms_min": 2.0, "frame_ms_max": 2.0,
            "stages_ms": {"shade": 1.0}, "metrics": {"rmse": 0.1, "mae": 0.05, "max_abs": 0.5, "psnr": 20.0, "ssim": 0.9, "flip_mean": 0.01, "flip_p95": 0.02, "flip_p99": 0.03,
            "penumbra_rmse": 0.2, "bad_pixel_share": 0.1, "nan_count": 0}
        });
        for (path, v) in changes.as_object().unwrap() {
            match path.split_once('.') {
                Some((a, b)) => r[a][b] = v.clone(),
                None => r[path] = v.clone(),
            }
        }
        r.to_string() + "\n"
    };
    std::fs::write(dir.join("good.jsonl"), row(serde_json::json!({}))).unwrap();
    let o = run_in(&dir, &["report", "good.jsonl", "--out", "fine"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for (name, changes, want) in [
        ("rmse", serde_json::json!({"metrics.rmse": 1e308, "rmse": 1e308}), "line 1: metrics.rmse = 1e308: an error or share of V lies in [0, 1]"),
        ("negative", serde_json::json!({"metrics.rmse": -1.0, "rmse": -1.0}), "line 1: metrics.rmse = -1: an error or share of V lies in [0, 1]"),
        ("twice", serde_json::json!({"rmse": 0.2}), "line 1: rmse = 0.2: differs from metrics.rmse = 0.1"),
        ("time", serde_json::json!({"frame_ms": 1e308}), "line 1: frame_ms = 1e308: a time in ms must be finite, at least 0 and at most 1e12 (a year is 3.2e10)"),
        ("stage", serde_json::json!({"stages_ms": {"shade": -3.0}}), "line 1: stages_ms.shade = -3: a time in ms must be finite"),
    ] {
        std::fs::write(dir.join(format!("{name}.jsonl")), row(changes)).unwrap();
        let e = refused(&dir, &["report", &format!("{name}.jsonl"), "--out", "out"]);
        assert!(e.starts_with(&format!("report: {name}.jsonl: {want}")), "{name}: {e}");
    }
}

/// `calibrate --out` the estimate's own folder would replace the set that holds its input: refused,
/// naming both, and the folder is left as it was. `merge` into a shard's own folder likewise.
#[test]
fn a_run_whose_input_lies_in_the_set_it_replaces_is_refused() {
    let dir = temp_dir("bad_files_own_folder");
    std::fs::create_dir(dir.join("est")).unwrap();
    std::fs::write(
        dir.join("est/estimate.jsonl"),
        estimate_row(serde_json::json!({})),
    )
    .unwrap();
    std::fs::write(dir.join("est/.penumbra-set"), "estimate.jsonl\n").unwrap();
    let o = run_in(
        &dir,
        &[
            "calibrate",
            "--estimates",
            "est/estimate.jsonl",
            "--out",
            "est",
        ],
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert_eq!(
        e.trim(),
        "error: --estimates est/estimate.jsonl: lies inside the set --out est replaces (its entry estimate.jsonl, written by an earlier run, goes when the new set is written): the run would delete its own input; give another --out"
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("est/estimate.jsonl")).unwrap(),
        estimate_row(serde_json::json!({}))
    );
    // Another folder is fine, and so is a file in --out that the old set did not write.
    let o = run_in(
        &dir,
        &[
            "calibrate",
            "--estimates",
            "est/estimate.jsonl",
            "--out",
            "cal",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::copy(dir.join("est/estimate.jsonl"), dir.join("cal/mine.jsonl")).unwrap();
    let o = run_in(
        &dir,
        &["calibrate", "--estimates", "cal/mine.jsonl", "--out", "cal"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.join("cal/mine.jsonl").is_file());
    // merge into one of its shards' folders.
    std::fs::create_dir(dir.join("shard")).unwrap();
    std::fs::write(dir.join("shard/results.jsonl"), "{}\n").unwrap();
    std::fs::write(dir.join("shard/.penumbra-set"), "results.jsonl\n").unwrap();
    let o = run_in(&dir, &["merge", "shard", "--out", "shard"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.trim().starts_with(
            "error: DIR shard/results.jsonl: lies inside the set --out shard replaces"
        ),
        "{e}"
    );
}

/// `report` on a results folder: Markdown images and links out of the page lose their targets
/// (the page opens offline and holds no live link), rows files in sub-folders get their tables,
/// and an RMSE of -1 is kept as written and said.
#[test]
fn a_results_folder_page_fetches_nothing_and_says_what_it_holds() {
    let dir = temp_dir("bad_files_results_folder");
    std::fs::create_dir_all(dir.join("r/sub")).unwrap();
    std::fs::write(
        dir.join("r/README.md"),
        "# r\n\n![x](http://example.com/p.png) [click](javascript:alert(1)) [rows](rows.csv)\n",
    )
    .unwrap();
    std::fs::write(dir.join("r/rows.csv"), "a,rmse\n1,0.5\n").unwrap();
    std::fs::write(dir.join("r/sub/more.csv"), "a,rmse\n1,-1\n").unwrap();
    let o = run_in(&dir, &["report", "r", "--out", "out"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert_eq!(
        err.lines()
            .filter(|l| l.starts_with("warning:"))
            .collect::<Vec<_>>(),
        ["warning: r/sub/more.csv: line 2: rmse = -1: an error of V lies in [0, 1]"]
    );
    let page = std::fs::read_to_string(dir.join("out/report.html")).unwrap();
    for attr in ["src=\"http", "href=\"javascript", "href=\"http"] {
        assert!(!page.contains(attr), "{attr}: {page}");
    }
    assert!(
        page.contains("<a href=\"#rows.csv\">rows</a>")
            && page.contains("sub/more.csv (1 rows)")
            && page.contains("line 2: rmse = -1"),
        "{page}"
    );
}
