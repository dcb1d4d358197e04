//! Interrupt torture: a folder holding an earlier set and thousands of user files; runs into it are
//! signalled (SIGINT, SIGTERM, SIGKILL) at random points, each followed by an ordinary run. Every
//! user file must survive, checked by digest, and the folder must hold one whole set.
//!
//! CI runs 2,000 files and 10 points; the full size is
//! `PENUMBRA_TORTURE_FILES=100000 PENUMBRA_TORTURE_POINTS=30 cargo test --release --test interrupt_torture -- --nocapture`.
//!
//! Then SIGINT and SIGTERM over the last second of `estimate` and `frontier`, where the set is
//! committed: each must leave the older set or the newer one, whole, and no staging folder. CI
//! sends 4 of each; the 20: `PENUMBRA_LAST_SECOND_TRIALS=20`.
//!
//! Then signals 0-12 ms after the staging folder appears, while `estimate`, `calibrate`,
//! `frontier` and `convergence` write their sets (`after_staging`): CI sends 3 to each study, the
//! issue's 20 with `PENUMBRA_STAGING_TRIALS=20` (`PENUMBRA_STAGING_ROWS=FILE` appends a CSV row per
//! trial: study, trial, signal, ms after staging, set left, run finished, staging folders left).

mod common;
use penumbra_lab::record::output_set::MARKER;
use penumbra_lab::record::provenance::sha256_hex;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn setting(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .map(|v| {
            v.parse()
                .unwrap_or_else(|_| panic!("{name}={v}: not a count"))
        })
        .unwrap_or(default)
}

fn render_cmd(out: &Path, method: &str) -> std::process::Command {
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"));
    c.args([
        "render",
        "--scene",
        "default",
        "--method",
        method,
        "--set",
        "resolution=32",
        "--set",
        "shadow_map_size=64",
        "--out",
    ]);
    c.arg(out)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped());
    c
}

fn render(out: &Path, method: &str) {
    let r = render_cmd(out, method).output().unwrap();
    assert!(
        r.status.success(),
        "{method}: {}",
        String::from_utf8_lossy(&r.stderr)
    );
}

/// Every file under `dir` but the set's own entries and staging folders, with its digest.
fn user_files(dir: &Path, set: &[&str]) -> BTreeMap<PathBuf, String> {
    let mut files = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().into_owned();
            if d == dir
                && (set.contains(&name.as_str())
                    || name == MARKER
                    || name.starts_with(".penumbra-stage-"))
            {
                continue;
            }
            if e.file_type().unwrap().is_dir() {
                todo.push(e.path());
            } else {
                files.insert(
                    e.path().strip_prefix(dir).unwrap().to_path_buf(),
                    sha256_hex(&std::fs::read(e.path()).unwrap()),
                );
            }
        }
    }
    files
}

#[test]
fn no_user_file_is_lost_to_signals_at_random_points() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let (count, points) = (
        setting("PENUMBRA_TORTURE_FILES", 2000),
        setting("PENUMBRA_TORTURE_POINTS", 10),
    );
    let out = common::temp_dir("interrupt_torture").join("out");
    let set = ["run.json", "shaded.png", "visibility.exr", "visibility.png"];
    let t = Instant::now();
    render(&out, "hard");
    let run = t.elapsed();
    let mut rng = common::Lcg(0x5eed);
    // User files at the top (like notes) and in folders (like shards/ or a results archive).
    for i in 0..count {
        let path = if i % 10 == 0 {
            out.join(format!("note-{i}.txt"))
        } else {
            out.join(format!("user/d{}/f{i}.bin", i % 97))
        };
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        let bytes: Vec<u8> = (0..64 + i % 200)
            .map(|_| (rng.next_f32() * 256.0) as u8)
            .collect();
        std::fs::write(path, bytes).unwrap();
    }
    let before = user_files(&out, &set);
    assert_eq!(before.len(), count);
    let signals = [
        (libc::SIGINT, "SIGINT"),
        (libc::SIGTERM, "SIGTERM"),
        (libc::SIGKILL, "SIGKILL"),
    ];
    let mut cut = 0;
    for point in 0..points {
        let (sig, sig_name) = signals[point % 3];
        let delay = Duration::from_secs_f64(run.as_secs_f64() * 1.2 * rng.next_f32() as f64);
        let method = if point % 2 == 0 {
            "regular:n=3"
        } else {
            "hard"
        };
        let mut child = render_cmd(&out, method).spawn().unwrap();
        std::thread::sleep(delay);
        // SAFETY: signalling our own child by its id.
        unsafe { libc::kill(child.id() as i32, sig) };
        let status = child.wait().unwrap();
        cut += usize::from(!status.success());
        eprintln!(
            "point {point}: {sig_name} after {:.0} ms: {}",
            delay.as_secs_f64() * 1e3,
            if status.success() {
                "had finished"
            } else {
                "cut"
            }
        );
        render(&out, "hard");
        let after = user_files(&out, &set);
        let lost: Vec<_> = before
            .keys()
            .filter(|k| after.get(*k) != before.get(*k))
            .take(5)
            .collect();
        assert!(
            lost.is_empty(),
            "point {point} ({sig_name}): user files lost or changed, e.g. {lost:?}"
        );
        assert_eq!(after.len(), count, "point {point}: files appeared");
        let mut top: Vec<String> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        top.retain(|n| set.contains(&n.as_str()) || n.starts_with(".penumbra"));
        top.sort();
        assert_eq!(
            top,
            [
                MARKER,
                "run.json",
                "shaded.png",
                "visibility.exr",
                "visibility.png"
            ],
            "point {point}: not one whole set"
        );
    }
    eprintln!("{points} points, {cut} cut mid-run, {count} user files kept by digest; one run takes {:.0} ms", run.as_secs_f64() * 1e3);
    assert!(
        cut * 2 >= points,
        "only {cut} of {points} signals landed mid-run: the points do not test interrupts"
    );
}

/// Every file under `dir` (relative path → bytes), the set's marker included.
fn contents(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            if e.file_type().unwrap().is_dir() {
                todo.push(e.path());
            } else {
                files.insert(
                    e.path().strip_prefix(dir).unwrap().to_path_buf(),
                    std::fs::read(e.path()).unwrap(),
                );
            }
        }
    }
    files
}

fn study_cmd(study: &str, args: &[&str], out: &Path, cache: &Path) -> std::process::Command {
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"));
    c.current_dir(cache.parent().unwrap());
    c.arg(study).args(args).arg("--out").arg(out);
    c.env("PENUMBRA_NO_PROGRESS", "1")
        .env("PENUMBRA_CACHE", cache);
    c.stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null());
    c
}

/// Runs `study` with `older` into `out`, then, trial by trial, from a copy of that older set, runs
/// it with `newer` and signals it at d − 1 s + k · (1 s / trials), d being a whole run's duration:
/// the last second, where the set is written and committed. After each trial `out` must hold the
/// older set exactly or the newer one (the newer one's bytes exactly where `exact`; a study that
/// records timings is held to its file list and to every file differing from the older set's), and
/// no staging folder. The commit itself takes a millisecond or so, which timed signals seldom hit:
/// as many trials again are signalled the moment its journal appears, and must leave the newer set.
fn last_second(study: &str, older: &[&str], newer: &[&str], exact: bool, trials: usize) {
    // One study at a time: a second one beside it would make the measured duration a guess.
    static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _serial = SERIAL.lock().unwrap_or_else(|p| p.into_inner());
    let root = common::temp_dir(&format!("last_second_{study}"));
    std::fs::write(root.join("scene.toml"), common::SWEEP_SCENE).unwrap();
    let cache = root.join("cache");
    let (old_dir, new_dir, out) = (root.join("old"), root.join("new"), root.join("out"));
    let run = |args: &[&str], dir: &Path| {
        let s = study_cmd(study, args, dir, &cache).status().unwrap();
        assert!(s.success(), "{study} {args:?}: {s}");
    };
    run(older, &old_dir);
    // d: the median of three runs (the machine is shared).
    let mut runs: Vec<f64> = (0..3)
        .map(|_| {
            let _ = std::fs::remove_dir_all(&new_dir);
            let t = Instant::now();
            run(newer, &new_dir);
            t.elapsed().as_secs_f64()
        })
        .collect();
    runs.sort_by(f64::total_cmp);
    let d = runs[1];
    let (old, new) = (contents(&old_dir), contents(&new_dir));
    assert_ne!(old.keys().collect::<Vec<_>>(), Vec::<&PathBuf>::new());
    let mut tally = BTreeMap::new();
    for (sig, sig_name) in [(libc::SIGINT, "SIGINT"), (libc::SIGTERM, "SIGTERM")] {
        // The timed trials, then as many again signalled the moment the commit's journal appears
        // (`at` None): those must leave the newer set.
        for k in (0..trials).map(Some).chain((0..trials).map(|_| None)) {
            let _ = std::fs::remove_dir_all(&out);
            let copy = std::process::Command::new("cp")
                .arg("-a")
                .arg(&old_dir)
                .arg(&out)
                .status()
                .unwrap();
            assert!(copy.success());
            let mut child = study_cmd(study, newer, &out, &cache).spawn().unwrap();
            let at = match k {
                Some(k) => {
                    let at = (d - 1.0 + k as f64 / trials as f64).max(0.0);
                    std::thread::sleep(Duration::from_secs_f64(at));
                    format!("{at:.2} s")
                }
                None => {
                    let journal = out
                        .join(format!(".penumbra-stage-{}", child.id()))
                        .join("commit");
                    while !journal.exists() && child.try_wait().unwrap().is_none() {
                        std::thread::sleep(Duration::from_micros(200));
                    }
                    "the journal".to_string()
                }
            };
            if child.try_wait().unwrap().is_none() {
                // SAFETY: signalling our own child, not yet reaped, by its id.
                unsafe { libc::kill(child.id() as i32, sig) };
            }
            let status = child.wait().unwrap();
            // A cut run ends by the signal itself, as an uncaught one would end it.
            use std::os::unix::process::ExitStatusExt;
            assert!(
                status.success() || status.signal() == Some(sig),
                "{study} {sig_name} at {at}: {status}"
            );
            let now = contents(&out);
            let hidden: Vec<_> = std::fs::read_dir(&out)
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with(".penumbra-stage-"))
                .collect();
            assert!(
                hidden.is_empty(),
                "{study} {sig_name} at {at} ({status}): staging folder left: {hidden:?}"
            );
            let is_new = now.keys().eq(new.keys())
                && now
                    .iter()
                    .all(|(p, b)| new[p] == *b || (!exact && old.get(p) != Some(b)));
            let outcome = if now == old {
                "old"
            } else if is_new {
                "new"
            } else {
                let mixed: Vec<String> = now
                    .iter()
                    .map(|(p, b)| {
                        format!(
                            "{} ({})",
                            p.display(),
                            if old.get(p) == Some(b) { "old" } else { "new" }
                        )
                    })
                    .collect();
                panic!("{study} {sig_name} at {at} ({status}): neither set: {mixed:?}");
            };
            if k.is_none() {
                assert_eq!(
                    outcome, "new",
                    "{study} {sig_name} at the journal ({status}): the commit was not finished"
                );
            }
            let when = if k.is_some() {
                "last second"
            } else {
                "at the journal"
            };
            *tally
                .entry((sig_name, when, outcome, status.success()))
                .or_insert(0) += 1;
        }
    }
    eprintln!("{study}: one run {d:.2} s (median of 3); {trials} signals of each kind over its last second and {trials} at the journal: {tally:?} ((signal, when, set left, run finished) → trials)");
    // The signals must land while the run is still going, or the test checks nothing.
    let cut: usize = tally
        .iter()
        .filter(|((_, _, _, finished), _)| !finished)
        .map(|(_, n)| n)
        .sum();
    assert!(
        cut * 2 >= trials * 2,
        "{study}: only {cut} of {} signals cut the run",
        trials * 2
    );
}

fn trials() -> usize {
    setting("PENUMBRA_LAST_SECOND_TRIALS", 4)
}

/// Runs `study` with `older` into `out`, then, trial by trial from a copy of that set, runs it with
/// `newer` and signals it k ms after its staging folder appears (k = 0..=12 in turn, SIGINT and
/// SIGTERM alternating): the window where the new set's files are written. Each trial must leave the
/// older set or the newer one (as `last_second` judges them) and no staging folder. Before, the
/// clean-up removed the folder while the writer recreated it, and `new/…` was left in 4 of 6
/// `estimate`, 5 of 12 `calibrate`, 2 of 10 `frontier` and 1 of 4 `convergence` trials. CI runs 3
/// trials of each study; the 20: `PENUMBRA_STAGING_TRIALS=20`. `prepare` makes inputs the
/// runs read, in the study's folder.
fn after_staging(
    study: &str,
    older: &[&str],
    newer: &[&str],
    exact: bool,
    prepare: &dyn Fn(&Path, &Path),
) {
    static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _serial = SERIAL.lock().unwrap_or_else(|p| p.into_inner());
    let trials = setting("PENUMBRA_STAGING_TRIALS", 3);
    let root = common::temp_dir(&format!("after_staging_{study}"));
    std::fs::write(root.join("scene.toml"), common::SWEEP_SCENE).unwrap();
    let cache = root.join("cache");
    prepare(&root, &cache);
    let (old_dir, new_dir, out) = (root.join("old"), root.join("new"), root.join("out"));
    for (args, dir) in [(older, &old_dir), (newer, &new_dir)] {
        let s = study_cmd(study, args, dir, &cache).status().unwrap();
        assert!(s.success(), "{study} {args:?}: {s}");
    }
    let (old, new) = (contents(&old_dir), contents(&new_dir));
    let mut tally = BTreeMap::new();
    for trial in 0..trials {
        let (sig, sig_name) = if trial % 2 == 0 {
            (libc::SIGINT, "SIGINT")
        } else {
            (libc::SIGTERM, "SIGTERM")
        };
        let ms = (trial % 13) as u64;
        let _ = std::fs::remove_dir_all(&out);
        assert!(std::process::Command::new("cp")
            .arg("-a")
            .arg(&old_dir)
            .arg(&out)
            .status()
            .unwrap()
            .success());
        let mut child = study_cmd(study, newer, &out, &cache).spawn().unwrap();
        let stage = out.join(format!(".penumbra-stage-{}", child.id()));
        while !stage.exists() && child.try_wait().unwrap().is_none() {
            std::thread::sleep(Duration::from_micros(100));
        }
        std::thread::sleep(Duration::from_millis(ms));
        if child.try_wait().unwrap().is_none() {
            // SAFETY: signalling our own child, not yet reaped, by its id.
            unsafe { libc::kill(child.id() as i32, sig) };
        }
        let status = child.wait().unwrap();
        use std::os::unix::process::ExitStatusExt;
        assert!(
            status.success() || status.signal() == Some(sig),
            "{study} {sig_name} {ms} ms after staging: {status}"
        );
        let hidden: Vec<_> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with(".penumbra-stage-"))
            .collect();
        assert!(
            hidden.is_empty(),
            "{study} {sig_name} {ms} ms after staging ({status}): staging folder left: {hidden:?}"
        );
        let now = contents(&out);
        let is_new = now.keys().eq(new.keys())
            && now
                .iter()
                .all(|(p, b)| new[p] == *b || (!exact && old.get(p) != Some(b)));
        let outcome = if now == old {
            "old"
        } else if is_new {
            "new"
        } else {
            panic!(
                "{study} {sig_name} {ms} ms after staging ({status}): neither set: {:?}",
                now.keys().collect::<Vec<_>>()
            );
        };
        *tally.entry((outcome, status.success())).or_insert(0) += 1;
        // PENUMBRA_STAGING_ROWS=FILE: one CSV row per trial (results/bad-input-census/).
        if let Ok(rows) = std::env::var("PENUMBRA_STAGING_ROWS") {
            use std::io::Write;
            let mut f = std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(rows)
                .unwrap();
            writeln!(
                f,
                "{study},{trial},{sig_name},{ms},{outcome},{},{}",
                status.success(),
                hidden.len()
            )
            .unwrap();
        }
    }
    eprintln!("{study}: {trials} signals 0-12 ms after the staging folder appeared: {tally:?} ((set left, run finished) → trials), no staging folder left");
}

/// A study's older and newer argument lists that differ in one value.
fn pair(args: &[&str], key: &str, older: &str, newer: &str) -> (Vec<String>, Vec<String>) {
    let with = |v: &str| {
        args.iter()
            .map(|a| a.to_string())
            .chain([key.to_string(), v.to_string()])
            .collect()
    };
    (with(older), with(newer))
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

const ESTIMATE: [&str; 4] = ["--scenes", "scene.toml", "--samples", "4"];

#[test]
fn signals_while_estimate_writes_its_set_leave_one_whole_set() {
    let _ = common::gpu();
    let (older, newer) = pair(&ESTIMATE, "--settings", "regular:n=2@64", "regular:n=3@64");
    after_staging("estimate", &strs(&older), &strs(&newer), true, &|_, _| {});
}

#[test]
fn signals_while_frontier_writes_its_set_leave_one_whole_set() {
    let _ = common::gpu();
    let args = [
        "--scene",
        "scene.toml",
        "--sizes",
        "64",
        "--hybrid",
        "none",
        "--repeats",
        "1",
        "--samples",
        "4",
    ];
    let (older, newer) = pair(&args, "--n", "2", "3");
    after_staging("frontier", &strs(&older), &strs(&newer), false, &|_, _| {});
}

#[test]
fn signals_while_convergence_writes_its_set_leave_one_whole_set() {
    let _ = common::gpu();
    let args = [
        "--scene",
        "scene.toml",
        "--samples",
        "4",
        "--set",
        "resolution=32",
    ];
    let (older, newer) = pair(&args, "--values", "2,3", "2,4");
    after_staging(
        "convergence",
        &strs(&older),
        &strs(&newer),
        true,
        &|_, _| {},
    );
}

#[test]
fn signals_while_calibrate_writes_its_set_leave_one_whole_set() {
    let _ = common::gpu();
    // Its input: two estimate files of the tiny scene.
    let prepare = |root: &Path, cache: &Path| {
        for n in ["2", "3"] {
            let args: Vec<&str> = ESTIMATE
                .iter()
                .copied()
                .chain([
                    "--settings",
                    if n == "2" {
                        "regular:n=2@64"
                    } else {
                        "regular:n=3@64"
                    },
                ])
                .collect();
            let s = study_cmd("estimate", &args, &root.join(format!("est{n}")), cache)
                .status()
                .unwrap();
            assert!(s.success());
        }
    };
    let args = ["--scenes", "scene.toml"];
    let (older, newer) = pair(
        &args,
        "--estimates",
        "est2/estimate.jsonl",
        "est2/estimate.jsonl,est3/estimate.jsonl",
    );
    after_staging("calibrate", &strs(&older), &strs(&newer), true, &prepare);
}

/// CI: 4 signals of each kind over `estimate`'s last second; the 20 with
/// `PENUMBRA_LAST_SECOND_TRIALS=20`.
#[test]
fn signals_in_the_last_second_of_estimate_leave_one_whole_set() {
    let _ = common::gpu();
    let args = |n: &str| {
        [
            "--scenes".to_string(),
            "scene.toml".into(),
            "--settings".into(),
            format!("regular:n={n}@64"),
            "--samples".into(),
            "4".into(),
        ]
    };
    let (older, newer) = (args("2"), args("3"));
    let (older, newer): (Vec<&str>, Vec<&str>) = (
        older.iter().map(String::as_str).collect(),
        newer.iter().map(String::as_str).collect(),
    );
    last_second("estimate", &older, &newer, true, trials());
}

/// The same over `frontier`'s last second; its records carry timings, so the newer set is known by
/// its files, each unlike the older set's.
#[test]
fn signals_in_the_last_second_of_frontier_leave_one_whole_set() {
    let _ = common::gpu();
    let common = [
        "--scene",
        "scene.toml",
        "--sizes",
        "64",
        "--hybrid",
        "none",
        "--repeats",
        "1",
        "--samples",
        "4",
    ];
    let older: Vec<&str> = common.iter().copied().chain(["--n", "2"]).collect();
    let newer: Vec<&str> = common.iter().copied().chain(["--n", "3"]).collect();
    last_second("frontier", &older, &newer, false, trials());
}
