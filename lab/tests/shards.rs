//! Sharded sweeps end to end on a tiny scene: shards merge into the rows one process makes,
//! concurrent shards on a cold reference cache trace the reference once, merge refuses what does
//! not belong together, and bad `--shard` / merge input gets one-line messages.

#[macro_use]
mod common;
use common::{ok, rows, temp_dir, untimed, SWEEP_SCENE as SCENE, SWEEP_SPEC as SPEC};
use std::path::Path;
use std::process::Command;

fn cmd(cache: &Path, args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_penumbra"));
    c.args(args)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .env("PENUMBRA_CACHE", cache);
    c
}

fn setup(name: &str) -> (std::path::PathBuf, String, String) {
    let dir = temp_dir(name);
    std::fs::write(dir.join("tiny.toml"), SCENE).unwrap();
    std::fs::write(dir.join("spec.toml"), SPEC).unwrap();
    let scene = dir.join("tiny.toml").to_string_lossy().into_owned();
    let spec = dir.join("spec.toml").to_string_lossy().into_owned();
    (dir, scene, spec)
}

#[test]
fn shards_merge_into_the_single_process_rows() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let (dir, scene, spec) = setup("shards_merge");
    let cache = dir.join("cache");
    let single = dir.join("single");
    let base = [
        "sweep",
        "--spec",
        &spec,
        "--scene",
        &scene,
        "--repeats",
        "1",
    ];
    let run = |extra: &[&str], out: &Path| {
        let mut args = base.to_vec();
        args.extend(extra);
        args.extend(["--out", out.to_str().unwrap()]);
        ok(cmd(&cache, &args).output().unwrap(), &format!("{args:?}"))
    };
    run(&[], &single);
    let shards: Vec<_> = (0..3).map(|i| dir.join(format!("shard{i}"))).collect();
    let mut counts = Vec::new();
    for (i, out) in shards.iter().enumerate() {
        run(&["--shard", &format!("{i}/3")], out);
        counts.push(rows(out).len());
    }
    assert_eq!(counts.iter().sum::<usize>(), 6, "{counts:?}");
    assert!(
        counts.iter().all(|&c| c >= 1),
        "every shard gets work: {counts:?}"
    );
    // regular:n=5 (26 units of cost) outweighs the rest: it runs alone or nearly so.
    let n5 = shards
        .iter()
        .position(|s| rows(s).iter().any(|r| r["label"] == "regular:n=5"))
        .unwrap();
    assert!(
        rows(&shards[n5]).len() <= 2,
        "cost-balanced, not count-balanced: {counts:?}"
    );

    let merged = dir.join("merged");
    let mut args = vec!["merge"];
    let names: Vec<String> = shards
        .iter()
        .rev()
        .map(|s| s.to_string_lossy().into_owned())
        .collect();
    args.extend(names.iter().map(String::as_str));
    args.extend(["--out", merged.to_str().unwrap()]);
    ok(cmd(&cache, &args).output().unwrap(), "merge");
    let (a, b) = (rows(&single), rows(&merged));
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(untimed(x), untimed(y), "rows differ beyond timing");
        for path in y["images"].as_object().unwrap().values() {
            assert!(
                merged.join(path.as_str().unwrap()).is_file(),
                "missing {path}"
            );
        }
    }
    let shards_seen: Vec<u64> = b
        .iter()
        .map(|r| r["provenance"]["spec"]["shard"][0].as_u64().unwrap())
        .collect();
    assert!(
        shards_seen.contains(&0) && shards_seen.contains(&2),
        "{shards_seen:?}"
    );
    let md = std::fs::read_to_string(merged.join("report.md")).unwrap();
    let line = md
        .lines()
        .find(|l| l.starts_with("| shards |"))
        .unwrap_or_else(|| panic!("the report lists the shards: {md}"));
    assert!(
        line.contains("0/3") && line.contains("1/3") && line.contains("2/3"),
        "{line}"
    );
    let merge_json = std::fs::read_to_string(merged.join("merge.json")).unwrap();
    assert!(merge_json.contains("shard 2/3 of"), "{merge_json}");

    // What does not belong together is refused, with one line naming it.
    let refuse = |args: &[&str], expected: &str| {
        let out = cmd(&cache, args).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    };
    let s = |p: &Path| p.to_string_lossy().into_owned();
    let out = s(&dir.join("refused"));
    refuse(
        &["merge", &s(&shards[0]), &s(&shards[1]), "--out", &out],
        "merge: shards 2/3 are missing (pass --allow partial",
    );
    refuse(
        &[
            "merge",
            &s(&shards[0]),
            &s(&shards[0]),
            &s(&shards[1]),
            "--out",
            &out,
        ],
        "given twice",
    );
    refuse(
        &["merge", &s(&single), &s(&shards[0]), "--out", &out],
        "is shard 0/3, ",
    );
    refuse(
        &["merge", &s(&dir.join("nowhere")), "--out", &out],
        "no results.jsonl in this folder",
    );
    refuse(
        &["merge", &s(&shards[0]), "--allow", "colour", "--out", &out],
        "--allow `colour`: not one of spec, version, adapter, scene, partial",
    );
    // Another version of the program: refused, unless allowed.
    let other = dir.join("other-version");
    std::fs::create_dir_all(&other).unwrap();
    let text = std::fs::read_to_string(shards[2].join("results.jsonl")).unwrap();
    let v: serde_json::Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    let git = v["version"]["git"].as_str().unwrap().to_string();
    std::fs::write(
        other.join("results.jsonl"),
        text.replace(&format!("\"git\":\"{git}\""), "\"git\":\"0000000\""),
    )
    .unwrap();
    refuse(
        &[
            "merge",
            &s(&shards[0]),
            &s(&shards[1]),
            &s(&other),
            "--out",
            &out,
        ],
        "(pass --allow version to merge anyway)",
    );
    // A shard of another spec.
    let spec2 = dir.join("spec2.toml");
    std::fs::write(&spec2, SPEC.replace("p_m = [0, 5]", "p_m = [0, 7]")).unwrap();
    let shard_other = dir.join("other-spec");
    ok(
        cmd(
            &cache,
            &[
                "sweep",
                "--spec",
                &s(&spec2),
                "--scene",
                &scene,
                "--repeats",
                "1",
                "--shard",
                "2/3",
                "--out",
                &s(&shard_other),
            ],
        )
        .output()
        .unwrap(),
        "other spec",
    );
    refuse(
        &[
            "merge",
            &s(&shards[0]),
            &s(&shards[1]),
            &s(&shard_other),
            "--out",
            &out,
        ],
        "(pass --allow spec to merge anyway)",
    );
    assert!(
        !dir.join("refused").exists(),
        "a refused merge writes nothing"
    );
}

#[test]
fn concurrent_shards_on_a_cold_cache_trace_the_reference_once() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let (dir, scene, spec) = setup("shards_concurrent");
    let cache = dir.join("cache");
    // The reference's cache key, from a run on a cache of its own.
    let probe = dir.join("probe");
    ok(
        cmd(
            &dir.join("probe-cache"),
            &[
                "reference",
                "--scene",
                &scene,
                "--out",
                probe.to_str().unwrap(),
            ],
        )
        .output()
        .unwrap(),
        "reference",
    );
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(probe.join("reference.json")).unwrap())
            .unwrap();
    let key = record["key"].as_str().unwrap().to_string();
    // Hold the entry's lock from this (live) process, so both shards provably start on the cold
    // cache at once and wait together; then let them race for it.
    // The lock is the OS's (flock): taken through the library, as a shard takes it.
    let refs = cache.join("reference");
    let lock = penumbra_lab::reference::lock(&refs, &key, &mut |who| {
        panic!("the cold cache's lock is held by {who}")
    })
    .unwrap();
    let start = |i: u32| {
        let out = dir.join(format!("shard{i}"));
        let log = std::fs::File::create(dir.join(format!("shard{i}.log"))).unwrap();
        let args = [
            "sweep",
            "--spec",
            &spec,
            "--scene",
            &scene,
            "--repeats",
            "1",
            "--shard",
            &format!("{i}/2"),
            "--out",
            out.to_str().unwrap(),
        ];
        cmd(&cache, &args)
            .stdout(std::process::Stdio::null())
            .stderr(log)
            .spawn()
            .unwrap()
    };
    let (mut a, mut b) = (start(0), start(1));
    let log =
        |i: u32| std::fs::read_to_string(dir.join(format!("shard{i}.log"))).unwrap_or_default();
    let waiting = |i: u32| log(i).contains("reference: waiting for");
    let t = std::time::Instant::now();
    while !(waiting(0) && waiting(1)) {
        assert!(
            t.elapsed().as_secs() < 120,
            "both shards should wait for the held lock:\n{}\n{}",
            log(0),
            log(1)
        );
        assert!(
            a.try_wait().unwrap().is_none() && b.try_wait().unwrap().is_none(),
            "a shard ended while the lock was held:\n{}\n{}",
            log(0),
            log(1)
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    drop(lock);
    let (sa, sb) = (a.wait().unwrap(), b.wait().unwrap());
    assert!(sa.success() && sb.success(), "{}\n{}", log(0), log(1));
    let traced: Vec<bool> = (0..2)
        .map(|i| {
            let r: serde_json::Value = serde_json::from_str(
                &std::fs::read_to_string(dir.join(format!("shard{i}/reference.json"))).unwrap(),
            )
            .unwrap();
            !r["cached"].as_bool().unwrap()
        })
        .collect();
    let logs = format!("{}\n{}", log(0), log(1));
    assert_eq!(
        traced.iter().filter(|t| **t).count(),
        1,
        "exactly one shard traces: {traced:?}\n{logs}"
    );
    let files: Vec<String> = std::fs::read_dir(cache.join("reference"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        files.len(),
        1,
        "one cache file, no lock or temporary left: {files:?}"
    );
    assert!(files[0].ends_with(".vis"));
    // Not torn: both shards hold the same reference, bit for bit, and it loads as a whole.
    let exr = |i: u32| std::fs::read(dir.join(format!("shard{i}/reference.exr"))).unwrap();
    assert_eq!(exr(0), exr(1));
    let bytes = std::fs::read(cache.join("reference").join(&files[0])).unwrap();
    assert_eq!(&bytes[..8], b"PNMBREF2");
    let entry = penumbra_lab::reference::parse_cache_file(&bytes).expect("whole, digest matching");
    assert_eq!(
        (entry.width, entry.height, entry.values.len()),
        (32, 32, 32 * 32)
    );

    // `--jobs 2` runs the same two shards as local processes and merges them.
    let jobs = dir.join("jobs");
    ok(
        cmd(
            &cache,
            &[
                "sweep",
                "--spec",
                &spec,
                "--scene",
                &scene,
                "--repeats",
                "1",
                "--jobs",
                "2",
                "--out",
                jobs.to_str().unwrap(),
            ],
        )
        .output()
        .unwrap(),
        "--jobs 2",
    );
    let merged = rows(&jobs);
    assert_eq!(merged.len(), 6);
    let labels: Vec<&str> = merged
        .iter()
        .map(|r| r["label"].as_str().unwrap())
        .collect();
    assert_eq!(
        labels,
        [
            "hard",
            "regular:n=2",
            "regular:n=3",
            "regular:n=5",
            "adaptive:p_m=0",
            "adaptive:p_m=5"
        ]
    );
}

#[test]
fn bad_shard_and_jobs_are_one_line_errors() {
    let (dir, scene, spec) = setup("shards_bad");
    let out = dir.join("out");
    for (extra, expected) in [
        (vec!["--shard", "3/3"], "error: --shard `3/3`: the index must be below the count (shards are numbered 0..2)"),
        (vec!["--shard", "x"], "error: --shard `x`: expected INDEX/COUNT, e.g. 0/4"),
        (vec!["--shard", "0/0"], "error: --shard `0/0`: the count must be in 1..=10000"),
        (vec!["--shard", "6/7"], "error: --shard 6/7: the spec has 6 configurations, too few for 7 shards"),
        (vec!["--shard", "99999999999/7"], "error: --shard `99999999999/7`: the index must be below the count (shards are numbered 0..6)"),
        (vec!["--jobs", "0"], "error: --jobs must be in 1..=64, got 0"),
        (vec!["--jobs", "2", "--shard", "0/2"], "error: --jobs 2: runs every shard itself; do not combine it with --shard"),
    ] {
        let mut args = vec!["sweep", "--spec", &spec, "--scene", &scene, "--out", out.to_str().unwrap()];
        args.extend(extra);
        let run = common::penumbra(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.starts_with(expected), "{stderr}");
        assert!(!out.exists());
    }
}

/// `--jobs K` on a spec of fewer configurations runs one shard per configuration and says so
/// (a shard with nothing to run used to fail after the others had run); when a shard fails, the
/// run writes nothing, not even the shards' folders.
#[test]
fn jobs_beyond_the_configurations_and_a_failed_shard() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let (dir, scene, _) = setup("shards_jobs_few");
    let spec = dir.join("two.toml");
    std::fs::write(&spec, "methods = [\"hard\", \"regular:n=2\"]\n").unwrap();
    let spec = spec.to_str().unwrap();
    let cache = dir.join("cache");
    let out = dir.join("out");
    let o = ok(
        cmd(
            &cache,
            &[
                "sweep",
                "--spec",
                spec,
                "--scene",
                &scene,
                "--repeats",
                "1",
                "--jobs",
                "3",
                "--out",
                out.to_str().unwrap(),
            ],
        )
        .output()
        .unwrap(),
        "--jobs 3",
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(
        stderr.lines().next(),
        Some("--jobs 3: the spec has 2 configurations; running 2 shards"),
        "{stderr}"
    );
    let labels: Vec<String> = rows(&out)
        .iter()
        .map(|r| r["label"].as_str().unwrap().to_string())
        .collect();
    assert_eq!(labels, ["hard", "regular:n=2"]);
    let mut shards: Vec<String> = std::fs::read_dir(out.join("shards"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    shards.sort();
    assert_eq!(shards, ["0", "1"]);

    // Each shard fails opening its adapter, after the parent started them.
    let failed = dir.join("failed");
    let o = cmd(
        &cache,
        &[
            "--adapter",
            "no-such-adapter-anywhere",
            "sweep",
            "--spec",
            spec,
            "--scene",
            &scene,
            "--jobs",
            "2",
            "--out",
            failed.to_str().unwrap(),
        ],
    )
    .output()
    .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().last(), Some("error: sweep --jobs 2: shards 0/2, 1/2 failed (their messages are above); nothing is written"), "{stderr}");
    assert_eq!(
        stderr
            .lines()
            .filter(|l| l.contains("no adapter's name contains it"))
            .count(),
        2,
        "{stderr}"
    );
    assert!(
        !failed.exists(),
        "wrote {:?}",
        std::fs::read_dir(&failed).map(|d| d.count())
    );
}
