//! Negative numbers given to numeric flags: one line naming the flag and the value (issue 26),
//! not "unexpected argument '-1' found" or clap's usage block; exit status 1, nothing runs and
//! nothing is written. Every flag that takes a value takes a negative number as its value
//! (src/cli/parse.rs), so no flag needs to ask for it.

mod common;

fn first_line_of_error(args: &[&str]) -> (Option<i32>, String, String) {
    let dir = common::temp_dir(&format!(
        "negative_flags_{}",
        args.join("_").replace(['/', '-', ' '], "")
    ));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(args)
        .current_dir(&dir)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .unwrap();
    let written: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(written.is_empty(), "{args:?} wrote {written:?}");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(
        stderr.lines().count(),
        1,
        "{args:?}: not one line: {stderr}"
    );
    (
        out.status.code(),
        stderr.lines().next().unwrap_or("").to_string(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
    )
}

#[test]
fn negative_numbers_name_their_flag() {
    let spec = common::temp_dir("negative_flags_spec").join("s.toml");
    std::fs::write(&spec, "methods = [\"hard\"]\n").unwrap();
    let spec = spec.to_str().unwrap();
    let cases: [(&[&str], &str); 10] = [
        (&["compare", "--repeats", "-1"], "error: --repeats: -1 is not in 0..=4294967295"),
        (&["sweep", "--spec", spec, "--shard", "-1/2"], "error: --shard `-1/2`: the index is not a non-negative integer"),
        (&["sequence", "--frames", "-1"], "error: --frames: -1 is not in 0..=4294967295"),
        (&["failures", "--frames", "-3"], "error: --frames: -3 is not in 0..=4294967295"),
        (&["render", "--warm-up", "-1"], "error: --warm-up: -1 is not in 0..=100"),
        (&["framing", "--scene", "default", "--light-scales", "-1,2"], "error: --light-scales: -1 is not in (0, 100]"),
        // A global flag, a count clap reads as a usize, a comma list: clap took each `-…` for a flag.
        (&["--max-mesh-mib", "-1", "scenes"], "error: --max-mesh-mib `-1`: must not be negative"),
        (&["frontier", "--max-configs", "-1"], "error: --max-configs `-1`: must not be negative"),
        (&["reference", "--mode", "point", "--point", "-0.5,0.5"], "error: --point: reference point `-0.5,0.5`: give S,T, two numbers in [0, 1] (0.5,0.5 is the light's centre)"),
        (&["sweep", "--spec", spec, "--shard", "99999999999/2"], "error: --shard `99999999999/2`: the index must be below the count (shards are numbered 0..1)"),
    ];
    for (args, want) in cases {
        let (code, line, stdout) = first_line_of_error(args);
        assert_eq!(code, Some(1), "{args:?}: exit {code:?}");
        assert_eq!(line, want, "{args:?}");
        assert!(stdout.is_empty(), "{args:?} printed {stdout}");
    }
}
