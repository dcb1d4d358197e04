//! A log reader that goes away (`penumbra compare 2>&1 | head -1`) ends the run with SIGPIPE, as
//! it ends other command-line tools, not with a panic in the next log line (exit 101), and leaves
//! no partial output set.

mod common;
use std::io::{BufRead, BufReader};
use std::os::unix::process::ExitStatusExt;

#[test]
fn a_closed_log_pipe_ends_the_run_without_a_panic() {
    let dir = common::temp_dir("closed_pipe");
    let out = dir.join("out");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args([
            "compare",
            "--set",
            "resolution=32",
            "--set",
            "shadow_map_size=64",
            "--methods",
            "hard,pcf,regular:n=3",
            "--repeats",
            "1",
            "--no-cache",
            "--out",
        ])
        .arg(&out)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stderr.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    // The reader is dropped here: the pipe's read end closes.
    let status = child.wait().unwrap();
    assert!(
        first.starts_with("reference continuous"),
        "first line: {first}"
    );
    assert_eq!(
        status.code(),
        None,
        "the run exited with {status} (101 is a panic), not by SIGPIPE"
    );
    assert_eq!(status.signal(), Some(libc::SIGPIPE), "{status}");
    assert!(
        !out.join("results.jsonl").exists(),
        "a run ended at its second log line wrote results"
    );
}
