//! Messages from the robustness probe of issue 26: each names what is wrong in words a user reads.

mod common;

fn run(args: &[&str]) -> (Option<i32>, String, String) {
    let out = common::penumbra(args);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn merge_errors_are_merges_not_the_reports() {
    let dir = common::temp_dir("messages_merge");
    std::fs::create_dir_all(dir.join("shard")).unwrap();
    std::fs::write(dir.join("shard/results.jsonl"), "{}\n").unwrap();
    let shard = dir.join("shard");
    let out = dir.join("out");
    let (code, stdout, stderr) = run(&[
        "merge",
        shard.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1));
    let want = format!(
        "error: merge: {}: line 1: not a result row: missing field `frame_ms_min` at line 1 column 2",
        shard.join("results.jsonl").display()
    );
    assert_eq!(stderr.trim(), want);
    assert!(stdout.is_empty() && !out.exists(), "wrote {stdout}");
}

#[test]
fn check_says_sizes_in_words_and_refuses_a_doubled_percent() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let dir = common::temp_dir("messages_check");
    let out = dir.join("run");
    let (code, _, stderr) = run(&[
        "compare",
        "--scene",
        "default",
        "--methods",
        "hard",
        "--set",
        "resolution=32",
        "--set",
        "shadow_map_size=64",
        "--repeats",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    let base = out.join("results.jsonl");
    let mut row: serde_json::Value = serde_json::from_str(
        std::fs::read_to_string(&base)
            .unwrap()
            .lines()
            .next()
            .unwrap(),
    )
    .unwrap();
    row["resolution"] = serde_json::json!([64, 64]);
    let other = dir.join("other.jsonl");
    std::fs::write(&other, format!("{row}\n")).unwrap();
    let (_, stdout, _) = run(&[
        "check",
        "--baseline",
        base.to_str().unwrap(),
        other.to_str().unwrap(),
    ]);
    assert!(stdout.contains("was measured differently (32x32 against continuous 32x32, now 64x64 against continuous 32x32): not comparable"), "{stdout}");
    assert!(!stdout.contains("Some("), "{stdout}");
    let (code, stdout, stderr) = run(&[
        "check",
        "--baseline",
        base.to_str().unwrap(),
        base.to_str().unwrap(),
        "--max",
        "rmse=+2%%",
    ]);
    assert_eq!(code, Some(1));
    assert_eq!(
        stderr.trim(),
        "error: --max `rmse=+2%%`: `+2%%` is not a number"
    );
    assert!(stdout.is_empty(), "{stdout}");
}

#[test]
fn a_scene_name_that_is_not_utf8_names_the_flag() {
    use std::os::unix::ffi::OsStrExt;
    let name = std::ffi::OsStr::from_bytes(b"\xff.toml");
    for command in ["render", "reference", "compare", "sequence"] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
            .args([command, "--scene"])
            .arg(name)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{command}: {stderr}");
        assert_eq!(
            stderr, "error: --scene: not valid UTF-8: \u{FFFD}.toml\n",
            "{command}"
        );
        assert!(out.stdout.is_empty(), "{command}: {stderr}");
    }
}

/// `assets fetch --cache FILE` said only "File exists", after printing what it would fetch.
#[test]
fn a_cache_that_is_a_file_names_the_flag_before_fetching() {
    let dir = common::temp_dir("messages_cache_file");
    let file = dir.join("F");
    std::fs::write(&file, "mine").unwrap();
    for (cache, want) in [
        (
            file.clone(),
            format!(
                "error: --cache {}: is a file, not a folder: give a folder for the asset cache",
                file.display()
            ),
        ),
        (
            file.join("sub"),
            format!(
                "error: --cache {}: {} is a file, not a folder: give a folder for the asset cache",
                file.join("sub").display(),
                file.display()
            ),
        ),
    ] {
        let (code, stdout, stderr) = run(&["assets", "fetch", "--cache", cache.to_str().unwrap()]);
        assert_eq!(code, Some(1), "{stderr}");
        assert_eq!(stderr.trim_end(), want);
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stdout.is_empty(), "printed {stdout}");
    }
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        1,
        "nothing beside the file"
    );
}
