//! Negative numbers given to numeric flags: the message names the flag and the value (issue 26),
//! not "unexpected argument '-1' found"; nothing runs and nothing is written.

mod common;

fn first_line_of_error(args: &[&str]) -> (Option<i32>, String, String) {
    let dir = common::temp_dir(&format!("negative_flags_{}", args.join("_").replace(['/', '-', ' '], "")));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(args)
        .current_dir(&dir)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .unwrap();
    let written: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(written.is_empty(), "{args:?} wrote {written:?}");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code(), stderr.lines().next().unwrap_or("").to_string(), String::from_utf8_lossy(&out.stdout).into_owned())
}

#[test]
fn negative_numbers_name_their_flag() {
    let spec = common::temp_dir("negative_flags_spec").join("s.toml");
    std::fs::write(&spec, "methods = [\"hard\"]\n").unwrap();
    let spec = spec.to_str().unwrap();
    let cases: [(&[&str], &str); 6] = [
        (&["compare", "--repeats", "-1"], "error: invalid value '-1' for '--repeats <REPEATS>': -1 is not in 0..=4294967295"),
        (&["sweep", "--spec", spec, "--shard", "-1/2"], "error: --shard `-1/2`: the index is not a non-negative integer"),
        (&["sequence", "--frames", "-1"], "error: invalid value '-1' for '--frames <FRAMES>': -1 is not in 0..=4294967295"),
        (&["failures", "--frames", "-3"], "error: invalid value '-3' for '--frames <FRAMES>': -3 is not in 0..=4294967295"),
        (&["render", "--warm-up", "-1"], "error: invalid value '-1' for '--warm-up <WARM_UP>': -1 is not in 0..=100"),
        (&["framing", "--scene", "default", "--light-scales", "-1,2"], "error: --light-scales: -1 is not in (0, 100]"),
    ];
    for (args, want) in cases {
        let (code, line, stdout) = first_line_of_error(args);
        assert!(matches!(code, Some(1) | Some(2)), "{args:?}: exit {code:?}");
        assert_eq!(line, want, "{args:?}");
        assert!(stdout.is_empty(), "{args:?} printed {stdout}");
    }
}
