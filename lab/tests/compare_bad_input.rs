//! Bad input to reference, compare, sweep, report and the studies' flags: one `error:` line, exit
//! status 1, no panic, no output folder and an untouched cache (nothing traced). All of it is
//! checked before the GPU starts, so no adapter is needed.

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
    assert_eq!(
        out.status.code(),
        Some(1),
        "{case}: exit {:?}, stderr: {stderr}",
        out.status.code()
    );
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
        (
            "unknown parameter",
            "regular:p_m=3",
            "has no parameter `p_m`",
        ),
        (
            "bad value",
            "adaptive:scope=everywhere",
            "scope = `everywhere`",
        ),
        ("listed twice", "adaptive,adaptive:p_m=0", "listed twice"),
    ];
    for (case, methods, needle) in cases {
        let line = fails(
            case,
            &[
                "compare",
                "--scene",
                "analytic-square",
                "--methods",
                methods,
            ],
            &dir,
        );
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
    assert!(
        line.contains("nope.jsonl") && line.contains("cannot read"),
        "{line}"
    );
    let bad = dir.join("bad.jsonl");
    std::fs::write(&bad, "{\"scene\": \"x\"}\n").unwrap();
    let line = fails("malformed", &["report", bad.to_str().unwrap()], &dir);
    assert!(
        line.contains("bad.jsonl") && line.contains("line 1"),
        "{line}"
    );
    let empty = dir.join("empty.jsonl");
    std::fs::write(&empty, "\n").unwrap();
    let line = fails("empty", &["report", empty.to_str().unwrap()], &dir);
    assert!(line.contains("no result rows"), "{line}");
}

#[test]
fn malformed_sweep_specs() {
    let dir = temp_dir("bad_sweep");
    let cases = [
        (
            "syntax",
            "[[grid]]\nmethod = \"regular\"\nn = [3, 5",
            "spec.toml",
        ),
        ("no method", "[[grid]]\nn = [3, 5]", "missing `method"),
        (
            "empty list",
            "[[grid]]\nmethod = \"regular\"\nn = []",
            "empty list",
        ),
        ("unknown key", "grids = 1", "unknown field"),
        ("nothing to run", "# empty\n", "nothing to run"),
        (
            "bad parameter",
            "[[grid]]\nmethod = \"regular\"\np_m = [1, 2]",
            "has no parameter `p_m`",
        ),
    ];
    for (case, text, needle) in cases {
        let spec = dir.join("spec.toml");
        std::fs::write(&spec, text).unwrap();
        let line = fails(
            case,
            &[
                "sweep",
                "--scene",
                "analytic-square",
                "--spec",
                spec.to_str().unwrap(),
            ],
            &dir,
        );
        assert!(line.contains(needle), "{case}: {line}");
    }
    let line = fails(
        "missing spec",
        &["sweep", "--spec", dir.join("absent.toml").to_str().unwrap()],
        &dir,
    );
    assert!(line.contains("absent.toml"), "{line}");
}

/// A value given twice to a list flag would be measured twice; every list flag refuses it the way
/// `--n` and `--sizes` do, naming the flag and the second value (as the first, when spelled apart).
#[test]
fn list_flags_refuse_a_value_given_twice() {
    let dir = temp_dir("bad_list_repeats");
    let cases: [(&[&str], &str); 9] = [
        (&["frontier", "--hybrid", "2048/2,1024/1,2048/2"], "error: --hybrid `2048/2`: listed twice"),
        (&["frontier", "--budget", "0.03,0.030"], "error: --budget `0.030`: listed twice (as `0.03`)"),
        (&["frontier", "--sizes", "512,0512"], "error: --sizes `0512`: listed twice (as `512`)"),
        (&["estimate", "--scenes", "analytic-square,analytic-square"], "error: --scenes `analytic-square`: listed twice"),
        (&["estimate", "--settings", "regular:n=3@512;regular:n=3,layout=lattice@512"], "error: --settings `regular:n=3,layout=lattice@512`: listed twice (as `regular:n=3@512`)"),
        (&["seams", "--scene", "point-edge", "--map-sizes", "256,512,256"], "error: --map-sizes `256`: listed twice"),
        (&["hybrid", "--hybrid", "2048/2,2048/2"], "error: --hybrid `2048/2`: listed twice"),
        (&["hybrid", "--plain", "512,1024", "--multi-plain", "256,256"], "error: --multi-plain `256`: listed twice"),
        (&["framing", "--scene", "analytic-square,analytic-square"], "error: --scene `analytic-square`: listed twice"),
    ];
    for (args, want) in cases {
        assert_eq!(fails(&args.join(" "), args, &dir), want);
    }
}

/// What the flags already fix is refused before any reference is traced or frame measured
/// (the hybrid study used to measure its hard part for 23 s first).
#[test]
fn study_flags_that_cannot_run_are_refused_up_front() {
    let dir = temp_dir("bad_study_flags");
    let cases: [(&[&str], &str); 4] = [
        (
            &["hybrid", "--scene", "point-edge", "--multi", "adaptive"],
            "error: --multi adaptive with --multi-hybrid 2048/2: adaptive: maps = hybrid is not supported with light kind `point` (a point light's cube maps need maps = plain: the hybrid store keeps one map per lattice sample); scene builtin:point-edge (use maps = plain)",
        ),
        (
            &["framing", "--scene", "point-edge", "--methods", "esm"],
            "error: --methods esm on --scene point-edge: esm: light kind `point` is not supported yet (its map looks from the rectangle's centre along the rectangle's normal); scene builtin:point-edge (docs/lights.md lists the pairs)",
        ),
        (
            &["seams", "--scene", "point-edge", "--set", "shadow_map_size=128"],
            "error: --set shadow_map_size=128: seams runs each map size of --map-sizes; give the sizes there (--map-sizes 128)",
        ),
        (
            &["estimate", "--scenes", "analytic-square", "--settings", "regular:n=3,estimate=off@512"],
            "error: --settings `regular:n=3,estimate=off@512`: `estimate` is set by the study (estimate = on is added); leave it out of the spec; give SPEC@SIZE, e.g. regular:n=5,layout=centred@1024",
        ),
    ];
    for (args, want) in cases {
        assert_eq!(fails(&args.join(" "), args, &dir), want);
    }
}
