//! The panic census's hook: a panic is appended to the log as one line, and the default hook
//! still runs. Its own test binary, since the hook is process-wide.

#[test]
fn a_panic_is_appended_to_the_log_as_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("panics.log");
    penumbra_lab::panic_log::install(log.clone());
    for k in 0..2 {
        let caught = std::panic::catch_unwind(|| panic!("probe {k}\nsecond line"));
        assert!(caught.is_err());
    }
    let text = std::fs::read_to_string(&log).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2, "{text}");
    for (k, line) in lines.iter().enumerate() {
        assert!(
            line.starts_with("panicked: panicked at lab/tests/panic_log.rs:"),
            "{line}"
        );
        assert!(line.contains(&format!("probe {k} second line")), "{line}");
        assert!(line.contains("(args: "), "{line}");
    }
}

/// The binary with the census's variable set: a bad input is refused in one line and leaves the
/// log unwritten (no panic), and the census script that sets it parses.
#[test]
fn the_binary_logs_nothing_for_a_refused_input_and_the_census_script_parses() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("panics.log");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args([
            "render",
            "--scene",
            "no-such-scene",
            "--out",
            dir.path().join("out").to_str().unwrap(),
        ])
        .env("PENUMBRA_PANIC_LOG", &log)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.starts_with("error: ") && stderr.contains("no-such-scene"),
        "{stderr}"
    );
    assert!(
        !log.exists(),
        "a refused input wrote the panic log: {:?}",
        std::fs::read_to_string(&log)
    );
    let script =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/panic-census.sh");
    let parse = std::process::Command::new("bash")
        .arg("-n")
        .arg(&script)
        .status()
        .unwrap();
    assert!(parse.success(), "bash -n {}", script.display());
}
