//! Interrupt torture: a folder holding an earlier set and thousands of user files; runs into it are
//! signalled (SIGINT, SIGTERM, SIGKILL) at random points, each followed by an ordinary run. Every
//! user file must survive, checked by digest, and the folder must hold one whole set.
//!
//! CI runs 2,000 files and 10 points; the full size is
//! `PENUMBRA_TORTURE_FILES=100000 PENUMBRA_TORTURE_POINTS=30 cargo test --release --test interrupt_torture -- --nocapture`.

mod common;
use penumbra::record::output_set::MARKER;
use penumbra::record::provenance::sha256_hex;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn setting(name: &str, default: usize) -> usize {
    std::env::var(name).ok().map(|v| v.parse().unwrap_or_else(|_| panic!("{name}={v}: not a count"))).unwrap_or(default)
}

fn render_cmd(out: &Path, method: &str) -> std::process::Command {
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"));
    c.args(["render", "--scene", "default", "--method", method, "--set", "resolution=32", "--set", "shadow_map_size=64", "--out"]);
    c.arg(out).env("PENUMBRA_NO_PROGRESS", "1").stdout(std::process::Stdio::null()).stderr(std::process::Stdio::piped());
    c
}

fn render(out: &Path, method: &str) {
    let r = render_cmd(out, method).output().unwrap();
    assert!(r.status.success(), "{method}: {}", String::from_utf8_lossy(&r.stderr));
}

/// Every file under `dir` but the set's own entries and staging folders, with its digest.
fn user_files(dir: &Path, set: &[&str]) -> BTreeMap<PathBuf, String> {
    let mut files = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().into_owned();
            if d == dir && (set.contains(&name.as_str()) || name == MARKER || name.starts_with(".penumbra-stage-")) {
                continue;
            }
            if e.file_type().unwrap().is_dir() {
                todo.push(e.path());
            } else {
                files.insert(e.path().strip_prefix(dir).unwrap().to_path_buf(), sha256_hex(&std::fs::read(e.path()).unwrap()));
            }
        }
    }
    files
}

#[test]
fn no_user_file_is_lost_to_signals_at_random_points() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let (count, points) = (setting("PENUMBRA_TORTURE_FILES", 2000), setting("PENUMBRA_TORTURE_POINTS", 10));
    let out = common::temp_dir("interrupt_torture").join("out");
    let set = ["run.json", "shaded.png", "visibility.exr", "visibility.png"];
    let t = Instant::now();
    render(&out, "hard");
    let run = t.elapsed();
    let mut rng = common::Lcg(0x5eed);
    // User files at the top (like notes) and in folders (like shards/ or a results archive).
    for i in 0..count {
        let path = if i % 10 == 0 { out.join(format!("note-{i}.txt")) } else { out.join(format!("user/d{}/f{i}.bin", i % 97)) };
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        let bytes: Vec<u8> = (0..64 + i % 200).map(|_| (rng.next_f32() * 256.0) as u8).collect();
        std::fs::write(path, bytes).unwrap();
    }
    let before = user_files(&out, &set);
    assert_eq!(before.len(), count);
    let signals = [(libc::SIGINT, "SIGINT"), (libc::SIGTERM, "SIGTERM"), (libc::SIGKILL, "SIGKILL")];
    let mut cut = 0;
    for point in 0..points {
        let (sig, sig_name) = signals[point % 3];
        let delay = Duration::from_secs_f64(run.as_secs_f64() * 1.2 * rng.next_f32() as f64);
        let method = if point % 2 == 0 { "regular:n=3" } else { "hard" };
        let mut child = render_cmd(&out, method).spawn().unwrap();
        std::thread::sleep(delay);
        // SAFETY: signalling our own child by its id.
        unsafe { libc::kill(child.id() as i32, sig) };
        let status = child.wait().unwrap();
        cut += usize::from(!status.success());
        eprintln!("point {point}: {sig_name} after {:.0} ms: {}", delay.as_secs_f64() * 1e3, if status.success() { "had finished" } else { "cut" });
        render(&out, "hard");
        let after = user_files(&out, &set);
        let lost: Vec<_> = before.keys().filter(|k| after.get(*k) != before.get(*k)).take(5).collect();
        assert!(lost.is_empty(), "point {point} ({sig_name}): user files lost or changed, e.g. {lost:?}");
        assert_eq!(after.len(), count, "point {point}: files appeared");
        let mut top: Vec<String> = std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        top.retain(|n| set.contains(&n.as_str()) || n.starts_with(".penumbra"));
        top.sort();
        assert_eq!(top, [MARKER, "run.json", "shaded.png", "visibility.exr", "visibility.png"], "point {point}: not one whole set");
    }
    eprintln!("{points} points, {cut} cut mid-run, {count} user files kept by digest; one run takes {:.0} ms", run.as_secs_f64() * 1e3);
    assert!(cut * 2 >= points, "only {cut} of {points} signals landed mid-run: the points do not test interrupts");
}
