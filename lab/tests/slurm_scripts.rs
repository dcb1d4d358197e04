//! scripts/slurm/ end to end without Slurm (issue 27). `submit.sh` runs the tiny sweep of
//! tests/shards.rs as 3 array tasks plus the merge job through the stand-in `sbatch`, `squeue` and
//! `scontrol` in tests/slurm-standin/ (local background processes; their headers say what they
//! honour). The merge job runs inside its `--out`, as Slurm's `--chdir` puts it there: its rows
//! must equal one process's, and the shards and the Slurm logs must stay; a second merge replaces
//! only the merged set; a failed shard leaves the merge job unrun. Also here, because
//! tests/shards.rs does not check them: `sweep --jobs 3` rows equal one process's, and a merge of
//! shards from another adapter is refused unless `--allow adapter` (`--allow version` likewise
//! accepts another binary's shard; the refusal itself is in tests/shards.rs).
//! The test against real Slurm is scripts/slurm-local-test.sh (root, not in CI).

#[macro_use]
mod common;
use common::{ok, rows, temp_dir, untimed, SWEEP_SCENE, SWEEP_SPEC};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

const SHARDS: usize = 3;
/// The longest the jobs of one submission may take before the test fails with their logs.
const WAIT: Duration = Duration::from_secs(300);

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn s(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

/// The stand-in Slurm of one test: its state folder, and commands with the stand-ins first on PATH.
struct Slurm {
    state: PathBuf,
    path: String,
}

impl Slurm {
    fn new(dir: &Path) -> Self {
        let standin = root().join("tests/slurm-standin");
        let path = format!(
            "{}:{}",
            standin.display(),
            std::env::var("PATH").unwrap_or_default()
        );
        Slurm {
            state: dir.join("slurm-state"),
            path,
        }
    }

    /// `program` (a stand-in by name, or a path) run from the repository root, as a user would.
    fn cmd(&self, program: &str) -> Command {
        let standin = root().join("tests/slurm-standin").join(program);
        let mut c = Command::new(if standin.is_file() {
            standin
        } else {
            PathBuf::from(program)
        });
        c.current_dir(root())
            .env("PATH", &self.path)
            .env("PENUMBRA_STANDIN_SLURM_DIR", &self.state)
            .env("PENUMBRA_NO_PROGRESS", "1")
            .env_remove("SBATCH_ARGS");
        c
    }

    /// `submit.sh SPEC OUT 3 --scene SCENE --repeats 1` with `binary` as PENUMBRA: (array, merge).
    fn submit(
        &self,
        spec: &str,
        out: &Path,
        scene: &str,
        binary: &str,
        cache: &Path,
    ) -> (String, String) {
        let shards = SHARDS.to_string();
        let run = self
            .cmd("scripts/slurm/submit.sh")
            .args([spec, &s(out), &shards, "--scene", scene, "--repeats", "1"])
            .env("PENUMBRA", binary)
            .env("PENUMBRA_CACHE", cache)
            .env("GRES", "")
            // What a cluster user passes; the stand-in accepts resource options and ignores them.
            .env("SBATCH_ARGS", "--time=10 --partition=standin")
            .output()
            .unwrap();
        let run = ok(run, "scripts/slurm/submit.sh");
        let stdout = String::from_utf8_lossy(&run.stdout).into_owned();
        let ids: Vec<&str> = stdout.split_whitespace().collect();
        assert_eq!(
            ids.len(),
            2,
            "submit.sh prints the array and merge job ids: {stdout}"
        );
        (ids[0].to_string(), ids[1].to_string())
    }

    /// Waits until `squeue -h -j IDS` lists nothing; past WAIT, ends the jobs and fails with their logs.
    fn wait(&self, ids: &[&str], out: &Path) {
        let t = Instant::now();
        loop {
            let q = ok(
                self.cmd("squeue")
                    .args(["-h", "-j", &ids.join(",")])
                    .output()
                    .unwrap(),
                "squeue",
            );
            if q.stdout.is_empty() {
                return;
            }
            if t.elapsed() > WAIT {
                self.end_all();
                panic!(
                    "jobs {ids:?} still queued after {WAIT:?}:\n{}\n{}",
                    String::from_utf8_lossy(&q.stdout),
                    self.logs(out)
                );
            }
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    /// The state of job `id` (every task's, for an array job), as `scontrol show job` reports it.
    fn states(&self, id: &str) -> Vec<String> {
        let run = ok(
            self.cmd("scontrol")
                .args(["show", "job", id])
                .output()
                .unwrap(),
            "scontrol",
        );
        let text = String::from_utf8_lossy(&run.stdout);
        let states: Vec<String> = text
            .split_whitespace()
            .filter_map(|w| w.strip_prefix("JobState="))
            .map(String::from)
            .collect();
        assert!(
            !states.is_empty(),
            "scontrol show job {id}: no JobState in {text}"
        );
        states
    }

    /// Every Slurm log in `out`, and the stand-in's own logs, for a failure message.
    fn logs(&self, out: &Path) -> String {
        let mut text = String::new();
        let mut files: Vec<PathBuf> = std::fs::read_dir(out)
            .map(|d| d.flatten().map(|e| e.path()).collect())
            .unwrap_or_default();
        files.extend(
            std::fs::read_dir(self.state.join("jobs"))
                .into_iter()
                .flatten()
                .flatten()
                .map(|e| e.path().join("runner.log")),
        );
        files.sort();
        for f in files
            .iter()
            .filter(|f| f.extension().is_some_and(|e| e == "out" || e == "log"))
        {
            text += &format!(
                "--- {}\n{}\n",
                f.display(),
                std::fs::read_to_string(f).unwrap_or_default()
            );
        }
        text
    }

    /// Ends the jobs' process groups (the stand-in sbatch starts each job in its own).
    fn end_all(&self) {
        for e in std::fs::read_dir(self.state.join("jobs"))
            .into_iter()
            .flatten()
            .flatten()
        {
            if let Ok(pgid) = std::fs::read_to_string(e.path().join("pgid")) {
                let _ = Command::new("kill")
                    .args(["-TERM", "--", &format!("-{}", pgid.trim())])
                    .output();
            }
        }
    }
}

fn setup(name: &str) -> (PathBuf, String, String) {
    let dir = temp_dir(name);
    std::fs::write(dir.join("tiny.toml"), SWEEP_SCENE).unwrap();
    std::fs::write(dir.join("spec.toml"), SWEEP_SPEC).unwrap();
    (
        dir.clone(),
        s(&dir.join("tiny.toml")),
        s(&dir.join("spec.toml")),
    )
}

fn penumbra(cache: &Path, args: &[&str]) -> Output {
    common::penumbra_env(args, &[("PENUMBRA_CACHE", &s(cache))])
}

fn assert_same_rows(expected: &[serde_json::Value], got: &Path, what: &str) {
    let got = rows(got);
    assert_eq!(expected.len(), got.len(), "{what}: row count");
    for (x, y) in expected.iter().zip(&got) {
        assert_eq!(
            untimed(x),
            untimed(y),
            "{what}: rows differ beyond timings and shard"
        );
    }
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// A copy of `shard` whose rows say `field` (`version` or `adapter`) is another one, as another
/// binary or another GPU would have written them.
fn tampered(shard: &Path, into: &Path, field: &str) -> PathBuf {
    ok(
        Command::new("cp")
            .args(["-r", &s(shard), &s(into)])
            .output()
            .unwrap(),
        "cp -r",
    );
    let text: Vec<String> = rows(into)
        .into_iter()
        .map(|mut r| {
            match field {
                "version" => r["version"]["git"] = "0000000".into(),
                _ => r["adapter"]["name"] = "Another GPU".into(),
            }
            serde_json::to_string(&r).unwrap()
        })
        .collect();
    std::fs::write(into.join("results.jsonl"), text.join("\n") + "\n").unwrap();
    into.to_path_buf()
}

#[test]
fn submit_sh_shards_and_merges_like_one_process() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let t0 = Instant::now();
    let (dir, scene, spec) = setup("slurm_scripts_submit");
    let bin = env!("CARGO_BIN_EXE_penumbra");

    // One process, then `--jobs 3` (tests/shards.rs checks only the labels of --jobs).
    let cache = dir.join("cache");
    let single = dir.join("single");
    ok(
        penumbra(
            &cache,
            &[
                "sweep",
                "--spec",
                &spec,
                "--scene",
                &scene,
                "--repeats",
                "1",
                "--out",
                &s(&single),
            ],
        ),
        "single-process sweep",
    );
    let expected = rows(&single);
    assert_eq!(expected.len(), 6);
    let jobs = dir.join("jobs");
    ok(
        penumbra(
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
                "3",
                "--out",
                &s(&jobs),
            ],
        ),
        "sweep --jobs 3",
    );
    assert_same_rows(&expected, &jobs, "sweep --jobs 3");
    let t_local = t0.elapsed();

    // Through the stand-in Slurm, on a cold cache of its own.
    let slurm = Slurm::new(&dir);
    let out = dir.join("out");
    let t1 = Instant::now();
    let (array, merge) = slurm.submit(&spec, &out, &scene, bin, &dir.join("cache-slurm"));
    slurm.wait(&[&array, &merge], &out);
    let t_slurm = t1.elapsed();
    let array_states = slurm.states(&array);
    assert_eq!(
        array_states,
        vec!["COMPLETED"; SHARDS],
        "array job {array}:\n{}",
        slurm.logs(&out)
    );
    for i in 0..SHARDS {
        assert!(
            out.join(format!("shards/{i}/results.jsonl")).is_file(),
            "shard {i}'s results"
        );
        let log = out.join(format!("penumbra-shard-{array}_{i}.out"));
        assert!(
            log.is_file(),
            "array task {i}'s Slurm log {}: {:?}",
            log.display(),
            names(&out)
        );
    }
    let traced = (0..SHARDS)
        .filter(|i| {
            let r: serde_json::Value = serde_json::from_str(
                &std::fs::read_to_string(out.join(format!("shards/{i}/reference.json"))).unwrap(),
            )
            .unwrap();
            r["cached"] == false
        })
        .count();
    assert_eq!(traced, 1, "the shards share one trace of the reference");

    // Shards of another binary or adapter (checked here, before the merge job's verdict, so that
    // they run whatever it says): refused with one line unless allowed.
    let shard = |i: usize| out.join(format!("shards/{i}"));
    let allow = |other: &Path, flag: &str, refusal: &[&str]| {
        let merged = dir.join(format!("allow-{flag}"));
        let inputs = [s(&shard(0)), s(&shard(1)), s(other)];
        let mut args: Vec<&str> = vec!["merge"];
        args.extend(inputs.iter().map(String::as_str));
        let target = s(&merged);
        args.extend(["--out", &target]);
        if !refusal.is_empty() {
            let run = penumbra(&cache, &args);
            let stderr = String::from_utf8_lossy(&run.stderr);
            assert_eq!(run.status.code(), Some(1), "{stderr}");
            assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
            assert!(
                refusal.iter().all(|r| stderr.contains(r)),
                "{refusal:?}: {stderr}"
            );
            assert!(!merged.exists(), "a refused merge writes nothing");
        }
        args.extend(["--allow", flag]);
        ok(penumbra(&cache, &args), &format!("merge --allow {flag}"));
        assert_eq!(rows(&merged).len(), 6, "merge --allow {flag}");
    };
    let other_adapter = tampered(&shard(2), &dir.join("other-adapter"), "adapter");
    allow(
        &other_adapter,
        "adapter",
        &[
            "has adapter",
            "Another GPU",
            "(pass --allow adapter to merge anyway)",
        ],
    );
    allow(
        &tampered(&shard(2), &dir.join("other-version"), "version"),
        "version",
        &[],
    );

    // The merge job: run inside its --out (Slurm's --chdir), it must complete, leave the shards and
    // the logs beside the merged set, and give one process's rows.
    let merge_log = out.join(format!("penumbra-merge-{merge}.out"));
    let merge_states = slurm.states(&merge);
    assert_eq!(
        merge_states,
        ["COMPLETED"],
        "merge job {merge}: {}",
        std::fs::read_to_string(&merge_log).unwrap_or_else(|e| format!("no log: {e}"))
    );
    assert!(
        merge_log.is_file(),
        "the merge job's Slurm log stays in {}: {:?}",
        out.display(),
        names(&out)
    );
    assert_same_rows(&expected, &out, "slurm shards + merge job");
    for i in 0..SHARDS {
        assert!(
            out.join(format!("shards/{i}/results.jsonl")).is_file(),
            "shard {i} survives the merge: {:?}",
            names(&out)
        );
        assert!(
            out.join(format!("penumbra-shard-{array}_{i}.out"))
                .is_file(),
            "task {i}'s log survives the merge: {:?}",
            names(&out)
        );
    }
    let hidden: Vec<String> = names(&out)
        .into_iter()
        .filter(|n| n.starts_with('.') && n != ".penumbra-set")
        .collect();
    assert!(
        hidden.is_empty(),
        "no staging left in {}: {hidden:?}",
        out.display()
    );

    // Merge again (merge.sbatch through sbatch): only the merged set is replaced. A user's file, the
    // shards and the logs stay; a file of the old set that the new one does not write goes.
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    std::fs::write(out.join("report.md"), "stale").unwrap();
    std::fs::write(out.join("stale-chart.svg"), "<svg/>").unwrap();
    let marker = out.join(".penumbra-set");
    let listed =
        std::fs::read_to_string(&marker).unwrap_or_else(|e| panic!("{}: {e}", marker.display()));
    std::fs::write(&marker, listed + "stale-chart.svg\n").unwrap();
    let shard_rows: Vec<_> = (0..SHARDS).map(|i| rows(&shard(i))).collect();
    let t2 = Instant::now();
    let run = slurm
        .cmd("sbatch")
        .args([
            "--parsable",
            &format!("--chdir={}", out.display()),
            "scripts/slurm/merge.sbatch",
        ])
        .env("PENUMBRA", bin)
        .env("OUT", &out)
        .env("SHARDS", SHARDS.to_string())
        .output()
        .unwrap();
    let again = String::from_utf8_lossy(&ok(run, "sbatch merge.sbatch").stdout)
        .trim()
        .to_string();
    slurm.wait(&[&again], &out);
    let t_again = t2.elapsed();
    let again_log = out.join(format!("penumbra-merge-{again}.out"));
    assert_eq!(
        slurm.states(&again),
        ["COMPLETED"],
        "second merge job {again}: {}",
        std::fs::read_to_string(&again_log).unwrap_or_default()
    );
    assert_same_rows(&expected, &out, "second merge");
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine",
        "a user's file stays"
    );
    assert_ne!(
        std::fs::read_to_string(out.join("report.md")).unwrap(),
        "stale",
        "the set's files are replaced"
    );
    assert!(
        !out.join("stale-chart.svg").exists(),
        "a file of the old set that the new one does not write goes: {:?}",
        names(&out)
    );
    for (i, before) in shard_rows.iter().enumerate() {
        assert_eq!(&rows(&shard(i)), before, "shard {i} is left as it was");
        assert!(
            out.join(format!("penumbra-shard-{array}_{i}.out"))
                .is_file(),
            "task {i}'s log stays"
        );
    }
    assert!(
        merge_log.is_file() && again_log.is_file(),
        "both merge logs stay: {:?}",
        names(&out)
    );
    eprintln!(
        "slurm_scripts: single + --jobs 3 {:.1} s, submit to merged {:.1} s, merge again {:.1} s, whole test {:.1} s",
        t_local.as_secs_f64(),
        t_slurm.as_secs_f64(),
        t_again.as_secs_f64(),
        t0.elapsed().as_secs_f64()
    );
}

#[test]
fn a_failed_shard_leaves_the_merge_job_unrun() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let t0 = Instant::now();
    let (dir, scene, spec) = setup("slurm_scripts_failed_shard");
    // PENUMBRA names a wrapper that fails array task 1, as a crashed node would; the others run.
    let wrapper = dir.join("penumbra-fails-task-1");
    std::fs::write(
        &wrapper,
        format!(
            "#!/bin/bash\nif [ \"${{SLURM_ARRAY_TASK_ID:-}}\" = 1 ]; then echo 'injected failure of task 1' >&2; exit 3; fi\nexec '{}' \"$@\"\n",
            env!("CARGO_BIN_EXE_penumbra")
        ),
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&wrapper, std::fs::Permissions::from_mode(0o755)).unwrap();

    let slurm = Slurm::new(&dir);
    let out = dir.join("out");
    let (array, merge) = slurm.submit(&spec, &out, &scene, &s(&wrapper), &dir.join("cache"));
    slurm.wait(&[&array, &merge], &out);
    assert_eq!(
        slurm.states(&array),
        ["COMPLETED", "FAILED", "COMPLETED"],
        "{}",
        slurm.logs(&out)
    );
    let log1 = std::fs::read_to_string(out.join(format!("penumbra-shard-{array}_1.out"))).unwrap();
    assert!(log1.contains("injected failure of task 1"), "{log1}");
    assert_eq!(
        slurm.states(&merge),
        ["CANCELLED"],
        "afterok: the merge job never runs after a failed shard"
    );
    let run = ok(
        slurm
            .cmd("scontrol")
            .args(["show", "job", &merge])
            .output()
            .unwrap(),
        "scontrol",
    );
    assert!(String::from_utf8_lossy(&run.stdout).contains("Reason=DependencyNeverSatisfied"));
    assert!(
        !out.join(format!("penumbra-merge-{merge}.out")).exists(),
        "the merge job did not run: {:?}",
        names(&out)
    );
    assert!(
        !out.join("results.jsonl").exists(),
        "no merged results: {:?}",
        names(&out)
    );
    assert!(
        !out.join("shards/1").exists(),
        "the failed shard wrote nothing"
    );
    eprintln!(
        "slurm_scripts: failed shard {:.1} s",
        t0.elapsed().as_secs_f64()
    );
}
