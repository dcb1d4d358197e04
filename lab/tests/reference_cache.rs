//! The reference cache is checked on read (docs/robustness.md, "The reference cache"): an entry
//! whose bytes were damaged with its size kept (flipped bytes, a zeroed run, 7.0 or NaN written
//! over a value) or one in the old format without a digest is never used. One warning line names
//! the file, the reference is traced again and replaces it, and the figures equal a clean run's.
//! A cache file that cannot be read at all is refused with one line naming it and `--no-cache`.

mod common;
use common::temp_dir;
use std::path::{Path, PathBuf};
use std::process::Output;

/// A box over a plane at 32x32: the sweep tests' tiny scene.
const SCENE: &str = common::SWEEP_SCENE;

fn compare(cache: &Path, scene: &Path, out: &Path) -> Output {
    let args = [
        "compare", "--scene", scene.to_str().unwrap(), "--methods", "hard", "--reference", "lattice", "--repeats", "1",
        "--out", out.to_str().unwrap(),
    ];
    common::penumbra_env(&args, &[("PENUMBRA_CACHE", cache.to_str().unwrap())])
}

/// (RMSE of `hard`, stderr) of a run that must succeed.
fn rmse_of(out: Output, dir: &Path) -> (f64, String) {
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "compare failed: {}{err}", String::from_utf8_lossy(&out.stdout));
    let rows = common::rows(dir);
    (rows[0]["metrics"]["rmse"].as_f64().unwrap(), err)
}

fn the_cache_file(cache: &Path) -> PathBuf {
    let files: Vec<PathBuf> = std::fs::read_dir(cache.join("reference")).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(files.len(), 1, "{files:?}");
    files[0].clone()
}

fn warnings(stderr: &str) -> Vec<&str> {
    stderr.lines().filter(|l| l.starts_with("warning:")).collect()
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
    cases.push(("the old format", old, "is in the old cache format (PNMBREF1, no digest)"));

    for (what, bytes, why) in cases {
        std::fs::write(&file, &bytes).unwrap();
        let (rmse, err) = rmse_of(compare(&cache, &scene, &out), &out);
        let expected = format!("warning: reference cache file {} {why}: not used; tracing the reference again", file.display());
        assert_eq!(warnings(&err), [expected.as_str()], "{what}: {err}");
        assert_eq!(rmse, clean, "{what}: the figure must equal the clean run's");
        assert_eq!(std::fs::read(&file).unwrap(), good, "{what}: the entry is replaced by the traced one");
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
        lines[0].starts_with(&format!("error: reference: cannot read the reference cache file {}: ", file.display()))
            && lines[0].ends_with("; remove it, or run with --no-cache to trace the reference afresh and replace it"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(out.join("results.jsonl")).unwrap(), before, "the old set stays");
    // --no-cache does not read it; the fresh result cannot replace a folder, and says where.
    let mut args = vec!["--no-cache"];
    args.extend(["compare", "--scene", scene.to_str().unwrap(), "--methods", "hard", "--reference", "lattice", "--repeats", "1", "--out", out.to_str().unwrap()]);
    args.rotate_left(1);
    let o = common::penumbra_env(&args, &[("PENUMBRA_CACHE", cache.to_str().unwrap())]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains(&format!("error: reference: cannot write the reference cache file {}: ", file.display())), "{err}");
}
