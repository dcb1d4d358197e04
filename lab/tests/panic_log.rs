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
        assert!(line.starts_with("panicked: panicked at lab/tests/panic_log.rs:"), "{line}");
        assert!(line.contains(&format!("probe {k} second line")), "{line}");
        assert!(line.contains("(args: "), "{line}");
    }
}
