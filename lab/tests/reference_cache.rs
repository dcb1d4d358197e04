//! The reference cache is checked on read (docs/robustness.md, "The reference cache"): an entry
//! whose bytes were damaged with its size kept (flipped bytes, a zeroed run, 7.0 or NaN written
//! over a value) or one in the old format without a digest is never used. One warning line names
//! the file, the reference is traced again and replaces it, and the figures equal a clean run's.
//! A cache file that cannot be read at all is refused with one line naming it and `--no-cache`,
//! which leaves the cache alone; a cache folder that cannot be written costs a trace, not the run;
//! a lock file left behind never blocks; a device in place of an entry is never read.

mod common;
use common::temp_dir;
use std::path::{Path, PathBuf};
use std::process::Output;

/// A box over a plane at 32x32: the sweep tests' tiny scene.
const SCENE: &str = common::SWEEP_SCENE;

fn compare(cache: &Path, scene: &Path, out: &Path) -> Output {
    let args = [
        "compare",
        "--scene",
        scene.to_str().unwrap(),
        "--methods",
        "hard",
        "--reference",
        "lattice",
        "--repeats",
        "1",
        "--out",
        out.to_str().unwrap(),
    ];
    common::penumbra_env(&args, &[("PENUMBRA_CACHE", cache.to_str().unwrap())])
}

/// (RMSE of `hard`, stderr) of a run that must succeed.
fn rmse_of(out: Output, dir: &Path) -> (f64, String) {
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(
        out.status.success(),
        "compare failed: {}{err}",
        String::from_utf8_lossy(&out.stdout)
    );
    let rows = common::rows(dir);
    (rows[0]["metrics"]["rmse"].as_f64().unwrap(), err)
}

fn the_cache_file(cache: &Path) -> PathBuf {
    let files: Vec<PathBuf> = std::fs::read_dir(cache.join("reference"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(files.len(), 1, "{files:?}");
    files[0].clone()
}

fn warnings(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .collect()
}

#[test]
fn a_damaged_entry_is_traced_again_with_one_warning_and_the_same_figures() {
    let _ = common::gpu();
    let dir = temp_dir("reference_cache_damaged");
    let (cache, scene, out) = (dir.join("cache"), dir.join("s.toml"), dir.join("out"));
    std::fs::write(&scene, SCENE).unwrap();
    let (clean, err) = rmse_of(compare(&cache, &scene, &out), &out);
    assert!(warnings(&err).is_empty(), "{err}");
    assert!(clean > 0.01 && clean < 0.5, "hard's RMSE {clean}");
    let file = the_cache_file(&cache);
    let good = std::fs::read(&file).unwrap();
    let entry = penumbra_lab::reference::parse_cache_file(&good).unwrap();
    let data_at = 20 + entry.key.len();
    // A lit pixel's value, so that 7.0 and NaN replace a real figure.
    let lit = data_at + 4 * entry.values.iter().position(|&v| v > 0.5).unwrap();

    let digest = "does not match its sha256 digest: its bytes were damaged";
    let mut cases: Vec<(&str, Vec<u8>, &str)> = Vec::new();
    let mut flipped = good.clone();
    flipped[lit + 2] ^= 0x5a;
    cases.push(("flipped bytes", flipped, digest));
    let mut zeroed = good.clone();
    zeroed[lit..lit + 256].fill(0);
    cases.push(("a zeroed run", zeroed, digest));
    for v in [7.0f32, f32::NAN] {
        let mut written = good.clone();
        written[lit..lit + 4].copy_from_slice(&v.to_le_bytes());
        cases.push(("a value out of range", written, digest));
    }
    let mut old = good[..good.len() - 32].to_vec();
    old[..8].copy_from_slice(b"PNMBREF1");
    cases.push((
        "the old format",
        old,
        "is in the old cache format (PNMBREF1, no digest)",
    ));

    for (what, bytes, why) in cases {
        std::fs::write(&file, &bytes).unwrap();
        let (rmse, err) = rmse_of(compare(&cache, &scene, &out), &out);
        let expected = format!(
            "warning: reference cache file {} {why}: not used; tracing the reference again",
            file.display()
        );
        assert_eq!(warnings(&err), [expected.as_str()], "{what}: {err}");
        assert_eq!(rmse, clean, "{what}: the figure must equal the clean run's");
        assert_eq!(
            std::fs::read(&file).unwrap(),
            good,
            "{what}: the entry is replaced by the traced one"
        );
    }
    // The replaced entry is read again, with no warning.
    let (rmse, err) = rmse_of(compare(&cache, &scene, &out), &out);
    assert!(warnings(&err).is_empty(), "{err}");
    assert_eq!(rmse, clean);
}

#[test]
fn an_unreadable_entry_is_one_error_naming_the_file_and_no_cache() {
    let _ = common::gpu();
    let dir = temp_dir("reference_cache_unreadable");
    let (cache, scene, out) = (dir.join("cache"), dir.join("s.toml"), dir.join("out"));
    std::fs::write(&scene, SCENE).unwrap();
    rmse_of(compare(&cache, &scene, &out), &out);
    let file = the_cache_file(&cache);
    // A folder under the entry's name: it exists, but no read gives bytes (root reads any file).
    std::fs::remove_file(&file).unwrap();
    std::fs::create_dir(&file).unwrap();
    let before = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    let o = compare(&cache, &scene, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(
        lines[0].starts_with(&format!(
            "error: reference: cannot read the reference cache file {}: ",
            file.display()
        )) && lines[0].ends_with(
            "; remove it, or run with --no-cache to trace the reference without the cache"
        ),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("results.jsonl")).unwrap(),
        before,
        "the old set stays"
    );
    // --no-cache does not touch the cache: the run traces, succeeds, and leaves the folder as it is.
    let args = [
        "compare",
        "--scene",
        scene.to_str().unwrap(),
        "--methods",
        "hard",
        "--reference",
        "lattice",
        "--repeats",
        "1",
        "--no-cache",
        "--out",
        out.to_str().unwrap(),
    ];
    let o = common::penumbra_env(&args, &[("PENUMBRA_CACHE", cache.to_str().unwrap())]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("cache"), "{err}");
    assert!(file.is_dir(), "--no-cache touched the cache");
}

/// Runs `args` as a user who cannot write `cache` (root passes every permission check, so as
/// root the run drops to nobody), in `dir`, which that user may write.
fn as_other_user(dir: &Path, args: &[&str], cache: &Path) -> Output {
    // SAFETY: geteuid has no preconditions.
    let root = unsafe { libc::geteuid() } == 0;
    let mut c = if root {
        let mut c = std::process::Command::new("setpriv");
        c.args(["--reuid=65534", "--regid=65534", "--clear-groups"])
            .arg(env!("CARGO_BIN_EXE_penumbra"));
        c
    } else {
        std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
    };
    c.current_dir(dir)
        .args(args)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .env("PENUMBRA_CACHE", cache)
        .output()
        .unwrap()
}

/// A cache folder this user cannot write: with --no-cache the run never touches it; without, the
/// reference is traced and not stored, and one warning names the folder. Before, both ended in
/// `error: reference: reference cache: Permission denied (os error 13)`, naming no path.
#[test]
fn a_read_only_cache_folder_costs_a_trace_not_the_run() {
    let _ = common::gpu();
    let dir = temp_dir("reference_cache_read_only");
    std::fs::write(dir.join("s.toml"), SCENE).unwrap();
    let cache = dir.join("cache");
    std::fs::create_dir_all(cache.join("reference")).unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o777)).unwrap();
    for p in [&cache, &cache.join("reference")] {
        std::fs::set_permissions(p, std::fs::Permissions::from_mode(0o555)).unwrap();
    }
    let args = |out: &'static str, no_cache: bool| {
        let mut a = vec![
            "compare",
            "--scene",
            "s.toml",
            "--methods",
            "hard",
            "--reference",
            "lattice",
            "--repeats",
            "1",
            "--out",
            out,
        ];
        if no_cache {
            a.push("--no-cache");
        }
        a
    };
    let o = as_other_user(&dir, &args("a", true), &cache);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("cache"), "{err}");
    let o = as_other_user(&dir, &args("b", false), &cache);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let said: Vec<&str> = err.lines().filter(|l| l.contains("cache")).collect();
    assert_eq!(said.len(), 1, "{err}");
    assert!(
        said[0].starts_with(&format!("warning: reference cache folder {}: ", cache.join("reference").display()))
            && said[0].ends_with(": the reference is traced and not stored (make the folder writable, or run with --no-cache to leave the cache alone)"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_dir(cache.join("reference")).unwrap().count(),
        0,
        "nothing stored"
    );
    assert_eq!(
        common::rows(&dir.join("a"))[0]["metrics"]["rmse"],
        common::rows(&dir.join("b"))[0]["metrics"]["rmse"]
    );
}

/// A lock file left by a signalled run whose pid now belongs to a live process (pid 1 here): the
/// lock is the OS's (`flock`), which died with its holder, so the next run takes it at once.
/// Before, the file's pid was asked, and every run needing the entry waited forever.
#[test]
fn a_lock_file_whose_pid_was_reused_is_taken_over() {
    let dir = temp_dir("reference_cache_stale_lock");
    let (cache, scene, out) = (dir.join("cache"), dir.join("s.toml"), dir.join("out"));
    std::fs::write(&scene, SCENE).unwrap();
    let (clean, _) = rmse_of(compare(&cache, &scene, &out), &out);
    let file = the_cache_file(&cache);
    std::fs::remove_file(&file).unwrap();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    std::fs::write(file.with_extension("lock"), format!("1 {}\n", host.trim())).unwrap();
    let t = std::time::Instant::now();
    let (rmse, err) = rmse_of(compare(&cache, &scene, &out), &out);
    assert!(
        t.elapsed() < std::time::Duration::from_secs(60) && !err.contains("waiting"),
        "{err}"
    );
    assert_eq!(rmse, clean);
    assert!(
        file.is_file() && !file.with_extension("lock").exists(),
        "the entry is written and the lock gone"
    );
}

/// A cache entry that is a link to /dev/zero (or any device): never opened; traced again and
/// replaced by a regular file, with one warning. Before, it was read until memory ran out.
#[test]
fn a_cache_entry_that_is_a_device_is_traced_again() {
    let dir = temp_dir("reference_cache_device");
    let (cache, scene, out) = (dir.join("cache"), dir.join("s.toml"), dir.join("out"));
    std::fs::write(&scene, SCENE).unwrap();
    let (clean, _) = rmse_of(compare(&cache, &scene, &out), &out);
    let file = the_cache_file(&cache);
    std::fs::remove_file(&file).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &file).unwrap();
    let (rmse, err) = rmse_of(compare(&cache, &scene, &out), &out);
    assert_eq!(warnings(&err), [format!("warning: reference cache file {} is a character device, not a regular file: not used; tracing the reference again", file.display())]);
    assert_eq!(rmse, clean);
    assert!(
        file.symlink_metadata().unwrap().is_file(),
        "replaced by the traced entry"
    );
}
