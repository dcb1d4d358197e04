//! Bad input to reference, compare, sweep and report: one `error:` line, exit status 1, no panic,
//! and no output folder. All of it is checked before the GPU starts, so no adapter is needed.

mod common;
use common::temp_dir;
use std::path::Path;
use std::process::Command;

fn fails(case: &str, args: &[&str], dir: &Path) -> String {
    let out_dir = dir.join("out");
    let mut all: Vec<&str> = args.to_vec();
    all.extend(["--out", out_dir.to_str().unwrap()]);
    let out = Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(&all)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .env("PENUMBRA_CACHE", dir.join("cache"))
        .output()
        .expect("run penumbra");
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(1), "{case}: exit {:?}, stderr: {stderr}", out.status.code());
    assert!(!stderr.contains("panicked"), "{case}: {stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{case}: expected one line, got: {stderr}");
    assert!(lines[0].starts_with("error: "), "{case}: {stderr}");
    assert!(!out_dir.exists(), "{case}: output folder was created");
    assert!(!dir.join("cache").exists(), "{case}: cache was touched");
    lines[0].to_string()
}

#[test]
fn bad_methods_lists() {
    let dir = temp_dir("bad_methods");
    let cases = [
        ("unknown method", "hard,phong", "unknown method `phong`"),
        ("dangling parameter", "p_m=0,hard", "no method before it"),
        ("empty entry", "hard,,adaptive", "empty entry"),
        ("unknown parameter", "regular:p_m=3", "has no parameter `p_m`"),
        ("bad value", "adaptive:scope=everywhere", "scope = `everywhere`"),
        ("listed twice", "adaptive,adaptive:p_m=0", "listed twice"),
    ];
    for (case, methods, needle) in cases {
        let line = fails(case, &["compare", "--scene", "analytic-square", "--methods", methods], &dir);
        assert!(line.contains(needle), "{case}: {line}");
    }
}

#[test]
fn bad_compare_settings() {
    let dir = temp_dir("bad_compare_settings");
    for (case, args, needle) in [
        ("repeats 0", vec!["compare", "--repeats", "0"], "--repeats"),
        ("reference mode", vec!["compare", "--reference", "exact"], "reference mode `exact`"),
        ("samples 0", vec!["compare", "--samples", "0"], "--samples"),
        ("method key in --set", vec!["compare", "--set", "p_m=3"], "--set p_m=3: p_m is a parameter of methods adaptive, env-adaptive, not a render setting; write it in the method spec (adaptive:p_m=3)"),
        ("missing scene", vec!["compare", "--scene", "no-such-scene.toml"], "no-such-scene.toml"),
        ("reference mode (reference)", vec!["reference", "--mode", "exact"], "reference mode `exact`"),
    ] {
        let line = fails(case, &args, &dir);
        assert!(line.contains(needle), "{case}: {line}");
    }
}

#[test]
fn missing_or_malformed_results_file() {
    let dir = temp_dir("bad_results");
    let missing = dir.join("nope.jsonl");
    let line = fails("missing", &["report", missing.to_str().unwrap()], &dir);
    assert!(line.contains("nope.jsonl") && line.contains("cannot read"), "{line}");
    let bad = dir.join("bad.jsonl");
    std::fs::write(&bad, "{\"scene\": \"x\"}\n").unwrap();
    let line = fails("malformed", &["report", bad.to_str().unwrap()], &dir);
    assert!(line.contains("bad.jsonl") && line.contains("line 1"), "{line}");
    let empty = dir.join("empty.jsonl");
    std::fs::write(&empty, "\n").unwrap();
    let line = fails("empty", &["report", empty.to_str().unwrap()], &dir);
    assert!(line.contains("no result rows"), "{line}");
}

#[test]
fn malformed_sweep_specs() {
    let dir = temp_dir("bad_sweep");
    let cases = [
        ("syntax", "[[grid]]\nmethod = \"regular\"\nn = [3, 5", "spec.toml"),
        ("no method", "[[grid]]\nn = [3, 5]", "missing `method"),
        ("empty list", "[[grid]]\nmethod = \"regular\"\nn = []", "empty list"),
        ("unknown key", "grids = 1", "unknown field"),
        ("nothing to run", "# empty\n", "nothing to run"),
        ("bad parameter", "[[grid]]\nmethod = \"regular\"\np_m = [1, 2]", "has no parameter `p_m`"),
    ];
    for (case, text, needle) in cases {
        let spec = dir.join("spec.toml");
        std::fs::write(&spec, text).unwrap();
        let line = fails(case, &["sweep", "--scene", "analytic-square", "--spec", spec.to_str().unwrap()], &dir);
        assert!(line.contains(needle), "{case}: {line}");
    }
    let line = fails("missing spec", &["sweep", "--spec", dir.join("absent.toml").to_str().unwrap()], &dir);
    assert!(line.contains("absent.toml"), "{line}");
}
