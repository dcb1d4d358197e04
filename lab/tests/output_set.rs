//! Outputs are written as a set (src/record/output_set/): staged inside --out and moved in at the end, user
//! entries left where they are.

mod common;
use penumbra_lab::record::output_set::{check, OutputSet, MARKER};
use std::path::{Path, PathBuf};

fn tmp(name: &str) -> PathBuf {
    common::temp_dir(&format!("output_set_{name}"))
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_new_set_replaces_the_old_one_and_keeps_foreign_entries() {
    let root = tmp("replace");
    let out = root.join("out");
    let s = OutputSet::begin(&out).unwrap();
    s.write("a.png", b"1").unwrap();
    s.write("stale.png", b"1").unwrap();
    s.write("sub/x.txt", b"1").unwrap();
    s.commit().unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let s = OutputSet::begin(&out).unwrap();
    s.write("a.png", b"2").unwrap();
    s.commit().unwrap();
    assert_eq!(names(&out), [MARKER, "a.png", "notes.txt"]);
    assert_eq!(std::fs::read(out.join("a.png")).unwrap(), b"2");
    assert_eq!(names(&root), ["out"], "no staging folder left");
}

#[test]
fn a_set_dropped_before_commit_leaves_the_old_set_and_no_debris() {
    let root = tmp("drop");
    let out = root.join("out");
    let s = OutputSet::begin(&out).unwrap();
    s.write("a.png", b"1").unwrap();
    s.commit().unwrap();
    let s = OutputSet::begin(&out).unwrap();
    s.write("a.png", b"2").unwrap();
    s.write("b.png", b"2").unwrap();
    drop(s);
    assert_eq!(names(&out), [MARKER, "a.png"]);
    assert_eq!(std::fs::read(out.join("a.png")).unwrap(), b"1");
    assert_eq!(names(&root), ["out"]);
}

#[test]
fn a_killed_runs_staging_folder_is_swept_by_the_next_run() {
    let root = tmp("sweep");
    let out = root.join("out");
    // No process has id 4294967: the folder is a killed run's.
    std::fs::create_dir_all(root.join(".out.partial-4294967/x")).unwrap();
    OutputSet::begin(&out).unwrap().commit().unwrap();
    assert_eq!(names(&root), ["out"]);
}

#[test]
fn out_that_is_a_file_is_refused() {
    let root = tmp("refuse");
    std::fs::write(root.join("f"), "x").unwrap();
    let e = check(&root.join("f")).unwrap_err().to_string();
    assert!(
        e.starts_with("--out ")
            && e.ends_with("f: is a file, not a folder: give a folder for the output set"),
        "{e}"
    );
    let e = check(&root.join("f/inner")).unwrap_err().to_string();
    assert!(e.contains("is a file, not a folder"), "{e}");
}

#[test]
fn a_folder_name_longer_than_the_file_system_takes_is_refused_before_any_work() {
    let root = tmp("long_name");
    let e = check(&root.join("n".repeat(256)).join("inner"))
        .unwrap_err()
        .to_string();
    assert!(
        e.ends_with("a folder name of 256 bytes is longer than the file system's limit of 255"),
        "{e}"
    );
    // 245 bytes fit: the staging folder's name no longer grows with it.
    let out = root.join("n".repeat(245));
    let s = OutputSet::begin(&out).unwrap();
    s.write("a.png", b"1").unwrap();
    s.commit().unwrap();
    assert_eq!(names(&out), [MARKER, "a.png"]);
}

fn render(out: &Path, method: &str) -> std::process::Output {
    common::penumbra(&[
        "render",
        "--scene",
        "default",
        "--method",
        method,
        "--set",
        "resolution=32",
        "--set",
        "shadow_map_size=64",
        "--out",
        out.to_str().unwrap(),
    ])
}

#[test]
fn a_render_replaces_an_earlier_adaptive_runs_pictures() {
    let out = tmp("stale").join("out");
    let first = render(&out, "adaptive");
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    assert!(out.join("comparison_map.png").exists() && out.join("light_quadtree.png").exists());
    let second = render(&out, "regular:n=3");
    assert!(
        second.status.success(),
        "{}",
        String::from_utf8_lossy(&second.stderr)
    );
    assert_eq!(
        names(&out),
        [
            MARKER,
            "run.json",
            "shaded.png",
            "visibility.exr",
            "visibility.png"
        ]
    );
    let record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(
        (record["method"].as_str(), record["params"]["n"].as_u64()),
        (Some("regular"), Some(3)),
        "{record}"
    );
    // The timed frame follows a warm-up on the same renderer, so no build is charged to it.
    assert_eq!(record["warm_up_frames"], 1, "{record}");
    assert!(
        record["stages_ms"]["shade"].as_f64().unwrap() > 0.0
            && record["stages_ms"].get("build").is_none(),
        "{record}"
    );
}

#[test]
fn out_that_is_a_file_is_refused_before_any_work_by_every_command() {
    let dir = tmp("out_file");
    let file = dir.join("taken");
    std::fs::write(&file, "x").unwrap();
    let f = file.to_str().unwrap();
    let spec = dir.join("spec.toml");
    std::fs::write(&spec, "methods = [\"hard\"]\n").unwrap();
    let cases: [Vec<&str>; 6] = [
        vec!["render", "--out", f],
        vec!["reference", "--out", f],
        vec!["compare", "--methods", "hard", "--out", f],
        vec!["sweep", "--spec", spec.to_str().unwrap(), "--out", f],
        vec!["--out", f],
        vec!["bench", "--suite", "seed-table2", "--out", f],
    ];
    for args in cases {
        let out = common::penumbra(&args);
        let e = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {e}");
        assert_eq!(
            e.trim(),
            format!("error: --out {f}: is a file, not a folder: give a folder for the output set"),
            "{args:?}"
        );
        assert!(
            out.stdout.is_empty(),
            "{args:?}: worked before failing: {}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "x");
}

#[test]
fn an_interrupted_render_leaves_the_old_set_or_the_new_one() {
    let root = tmp("interrupt");
    let out = root.join("out");
    assert!(render(&out, "hard").status.success());
    let old = std::fs::read(out.join("visibility.exr")).unwrap();
    let mut outcomes = Vec::new();
    for delay_ms in [10u64, 40, 80, 120, 160, 220, 300] {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
            .args([
                "render",
                "--scene",
                "default",
                "--method",
                "regular:n=3",
                "--set",
                "resolution=32",
                "--set",
                "shadow_map_size=64",
                "--out",
            ])
            .arg(&out)
            .env("PENUMBRA_NO_PROGRESS", "1")
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        // SAFETY: signalling our own child by its id.
        unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
        child.wait().unwrap();
        // SIGINT removes the staging folder (or finishes the commit) before the run ends.
        let files: Vec<String> = names(&out);
        let record: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("run.json")).unwrap()).unwrap();
        match record["method"].as_str() {
            Some("hard") => {
                assert_eq!(
                    files,
                    [
                        MARKER,
                        "run.json",
                        "shaded.png",
                        "visibility.exr",
                        "visibility.png"
                    ]
                );
                assert_eq!(
                    std::fs::read(out.join("visibility.exr")).unwrap(),
                    old,
                    "after {delay_ms} ms"
                );
            }
            Some("regular") => assert_eq!(
                files,
                [
                    MARKER,
                    "run.json",
                    "shaded.png",
                    "visibility.exr",
                    "visibility.png"
                ]
            ),
            m => panic!("after {delay_ms} ms: run.json names {m:?}"),
        }
        assert!(files.iter().all(|f| !f.ends_with(".tmp")), "{files:?}");
        outcomes.push(format!("{delay_ms} ms: {}", record["method"]));
    }
    println!("{outcomes:?}");
    // The next run sweeps any staging folder a killed run left.
    assert!(render(&out, "hard").status.success());
    assert_eq!(names(&root), ["out"]);
    assert_eq!(
        names(&out),
        [
            MARKER,
            "run.json",
            "shaded.png",
            "visibility.exr",
            "visibility.png"
        ]
    );
}

#[test]
fn an_output_name_taken_by_a_folder_is_replaced_with_no_temporary_left() {
    let out = tmp("name_is_dir").join("out");
    std::fs::create_dir_all(out.join("visibility.exr/inner")).unwrap();
    let r = render(&out, "hard");
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(out.join("visibility.exr").is_file());
    assert_eq!(
        names(&out),
        [
            MARKER,
            "run.json",
            "shaded.png",
            "visibility.exr",
            "visibility.png"
        ]
    );
    assert_eq!(names(out.parent().unwrap()), ["out"]);
}

fn render_in(cwd: &Path, out: &str, method: &str) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args([
            "render",
            "--scene",
            "default",
            "--method",
            method,
            "--set",
            "resolution=32",
            "--set",
            "shadow_map_size=64",
            "--out",
            out,
        ])
        .current_dir(cwd)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .unwrap()
}

/// A Slurm merge job runs with `--chdir=OUT` and writes `--out OUT`: the folder is never replaced,
/// so it may be the current one, and what else it holds stays.
#[test]
fn out_may_be_the_current_folder_and_its_other_entries_stay() {
    let out = tmp("cwd").join("out");
    std::fs::create_dir_all(out.join("shards/0")).unwrap();
    std::fs::write(out.join("shards/0/results.jsonl"), "{}").unwrap();
    std::fs::write(out.join("penumbra-merge-2.out"), "log").unwrap();
    for method in ["adaptive", "hard"] {
        let r = render_in(&out, ".", method);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    }
    assert_eq!(
        names(&out),
        [
            MARKER,
            "penumbra-merge-2.out",
            "run.json",
            "shaded.png",
            "shards",
            "visibility.exr",
            "visibility.png"
        ]
    );
    assert_eq!(
        std::fs::read_to_string(out.join("shards/0/results.jsonl")).unwrap(),
        "{}"
    );
}

#[test]
fn a_current_folder_inside_an_entry_the_set_replaces_is_refused_before_any_work() {
    let out = tmp("cwd_inside").join("out");
    let s = OutputSet::begin(&out).unwrap();
    s.write("images/a.png", b"1").unwrap();
    s.commit().unwrap();
    let r = render_in(&out.join("images"), "..", "hard");
    assert_eq!(r.status.code(), Some(1));
    assert_eq!(String::from_utf8_lossy(&r.stderr).trim(), "error: --out ..: the current folder is inside images, which the new set replaces: run from elsewhere");
    assert_eq!(names(&out), [MARKER, "images"]);
}

/// As an unprivileged user (CI runs as root, so the test drops to `nobody`), a read-only `--out`
/// is refused before any work, and the old set stays with no debris.
#[test]
fn a_read_only_out_is_refused_before_any_work() {
    use std::os::unix::fs::PermissionsExt;
    use std::os::unix::process::CommandExt;
    let root = tmp("read_only");
    let out = root.join("out");
    assert!(render(&out, "hard").status.success());
    let before = names(&out);
    let cache = root.join("cache");
    std::fs::create_dir_all(&cache).unwrap();
    for dir in [&root, &cache] {
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o777)).unwrap();
    }
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o555)).unwrap();
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"));
    cmd.args([
        "render",
        "--scene",
        "default",
        "--method",
        "hard",
        "--set",
        "resolution=32",
        "--out",
    ])
    .arg(&out);
    cmd.env("PENUMBRA_NO_PROGRESS", "1")
        .env("PENUMBRA_CACHE", &cache)
        .env("HOME", &cache);
    // SAFETY: reading our own effective user id.
    if unsafe { libc::geteuid() } == 0 {
        cmd.uid(65534).gid(65534);
    }
    let r = cmd.output().unwrap();
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o755)).unwrap();
    let e = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{e}");
    let want = format!(
        "error: --out {}: cannot write in {}: Permission denied (os error 13)",
        out.display(),
        out.display()
    );
    assert_eq!(e.trim(), want);
    assert!(
        r.stdout.is_empty(),
        "worked before failing: {}",
        String::from_utf8_lossy(&r.stdout)
    );
    assert_eq!(names(&out), before);
    assert_eq!(names(&root), ["cache", "out"]);
}
