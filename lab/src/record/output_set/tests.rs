//! A commit cut off at every point, then recovered by the next run: no user file is lost, and the
//! folder holds the old set (cut before the journal) or the new one (cut after).

use super::*;

fn tmp(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("penumbra-output-set-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn write_set(out: &Path, files: &[(&str, &str)]) -> OutputSet {
    let set = OutputSet::begin(out).unwrap();
    for (name, body) in files {
        set.write(name, body.as_bytes()).unwrap();
    }
    set
}

const OLD: &[(&str, &str)] = &[
    ("a.txt", "old a"),
    ("dir/x.txt", "old x"),
    ("only_old.txt", "old"),
];
const NEW: &[(&str, &str)] = &[
    ("a.txt", "new a"),
    ("b.txt", "new b"),
    ("dir/y.txt", "new y"),
];
const USER: &[(&str, &str)] = &[
    ("notes.txt", "mine"),
    ("shards/0/results.jsonl", "{}"),
    ("penumbra-merge-2.out", "log"),
];

/// The old set and the user's files, then the new set's commit cut after `steps` renames (`None`:
/// before its journal), as a SIGKILL would leave it: the staging folder stays, owned by a dead pid.
fn cut(root: &Path, steps: Option<usize>) -> PathBuf {
    let out = root.join("out");
    write_set(&out, OLD).commit().unwrap();
    for (name, body) in USER {
        let p = out.join(name);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, body).unwrap();
    }
    let set = write_set(&out, NEW);
    if let Some(mut steps) = steps {
        let journal = set.journal().unwrap();
        let r = journal.roll_forward_steps(set.folder(), &set.stage, &mut steps);
        assert!(r.is_ok() || r.unwrap_err().kind() == std::io::ErrorKind::Interrupted);
    }
    // No process has id 4294967: the folder is a killed run's.
    std::fs::rename(&set.stage, out.join(format!("{STAGE_PREFIX}4294967"))).unwrap();
    std::mem::forget(set);
    out
}

fn assert_user_files_kept(out: &Path) {
    for (name, body) in USER {
        assert_eq!(
            std::fs::read_to_string(out.join(name)).unwrap(),
            *body,
            "{name}"
        );
    }
}

#[test]
fn a_commit_cut_anywhere_is_finished_by_the_next_run_and_loses_no_user_file() {
    // 3 new entries (a.txt, dir aside first) + 1 gone + the marker: 8 renames in all.
    for steps in 0..=8 {
        let out = cut(&tmp(&format!("cut{steps}")), Some(steps));
        drop(OutputSet::begin(&out).unwrap());
        assert_user_files_kept(&out);
        assert_eq!(
            names(&out),
            [
                MARKER,
                "a.txt",
                "b.txt",
                "dir",
                "notes.txt",
                "penumbra-merge-2.out",
                "shards"
            ],
            "cut after {steps}"
        );
        assert_eq!(std::fs::read_to_string(out.join("a.txt")).unwrap(), "new a");
        assert_eq!(names(&out.join("dir")), ["y.txt"], "cut after {steps}");
        assert_eq!(
            std::fs::read_to_string(out.join(MARKER)).unwrap(),
            "a.txt\nb.txt\ndir\n"
        );
    }
}

#[test]
fn a_run_killed_before_its_journal_leaves_the_old_set() {
    let out = cut(&tmp("nojournal"), None);
    drop(OutputSet::begin(&out).unwrap());
    assert_user_files_kept(&out);
    assert_eq!(
        names(&out),
        [
            MARKER,
            "a.txt",
            "dir",
            "notes.txt",
            "only_old.txt",
            "penumbra-merge-2.out",
            "shards"
        ]
    );
    assert_eq!(std::fs::read_to_string(out.join("a.txt")).unwrap(), "old a");
}

#[test]
fn a_stale_staging_folder_holding_foreign_entries_is_kept() {
    let out = cut(&tmp("foreign"), None);
    let stale = out.join(format!("{STAGE_PREFIX}4294967"));
    std::fs::write(stale.join("someone-elses.txt"), "keep").unwrap();
    drop(OutputSet::begin(&out).unwrap());
    assert_eq!(names(&stale), ["someone-elses.txt"]);
}

#[test]
fn an_earlier_versions_staging_folder_gives_back_the_user_entries_it_carried() {
    let root = tmp("legacy");
    let out = root.join("out");
    write_set(&out, OLD).commit().unwrap();
    // That version wrote the new set and its marker beside `out`, then moved user entries in.
    let side = root.join(".out.partial-4294967");
    std::fs::create_dir_all(side.join("carried")).unwrap();
    std::fs::write(side.join("a.txt"), "new a").unwrap();
    std::fs::write(side.join(MARKER), "a.txt\n").unwrap();
    std::fs::write(side.join("carried/f.txt"), "mine").unwrap();
    std::fs::write(side.join("notes.txt"), "mine too").unwrap();
    drop(OutputSet::begin(&out).unwrap());
    assert_eq!(names(&root), ["out"]);
    assert_eq!(
        std::fs::read_to_string(out.join("carried/f.txt")).unwrap(),
        "mine"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine too"
    );
    assert_eq!(std::fs::read_to_string(out.join("a.txt")).unwrap(), "old a");
}
