//! The journal of a commit, and what a run does with the staging folders that killed runs left:
//! finish a journalled commit, drop an unfinished set, and hand back anything else to its folder.
//! Nothing that a set did not write is ever deleted here.

use super::{JOURNAL, MARKER, STAGE_PREFIX};
use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// What a commit moves: the new set's entries in, then the old set's other entries out.
pub(super) struct Journal {
    pub new: Vec<String>,
    pub gone: Vec<String>,
}

impl Journal {
    /// Written to a side name and renamed, so a journal is either whole or absent.
    pub fn write(&self, stage: &Path) -> Result<()> {
        let mut text = String::new();
        for n in &self.new {
            text += &format!("new\t{n}\n");
        }
        for n in &self.gone {
            text += &format!("gone\t{n}\n");
        }
        let tmp = stage.join(format!("{JOURNAL}.tmp"));
        std::fs::write(&tmp, text)
            .and_then(|_| std::fs::rename(&tmp, stage.join(JOURNAL)))
            .map_err(|e| Error::io(&tmp, e))
    }

    fn read(stage: &Path) -> Option<Self> {
        let text = std::fs::read_to_string(stage.join(JOURNAL)).ok()?;
        let mut j = Journal {
            new: Vec::new(),
            gone: Vec::new(),
        };
        for line in text.lines() {
            match line.split_once('\t') {
                Some(("new", n)) if safe(n) => j.new.push(n.to_string()),
                Some(("gone", n)) if safe(n) => j.gone.push(n.to_string()),
                _ => {}
            }
        }
        Some(j)
    }

    /// Each step is skipped once done, so this finishes a commit cut off at any point.
    pub fn roll_forward(&self, out: &Path, stage: &Path) -> std::io::Result<()> {
        let mut unlimited = usize::MAX;
        self.roll_forward_steps(out, stage, &mut unlimited)
    }

    /// At most `steps` renames, then an `Interrupted` error: how the tests cut a commit anywhere.
    pub fn roll_forward_steps(
        &self,
        out: &Path,
        stage: &Path,
        steps: &mut usize,
    ) -> std::io::Result<()> {
        std::fs::create_dir_all(stage.join("old"))?;
        for n in &self.new {
            move_in(out, stage, n, steps)?;
        }
        for n in &self.gone {
            set_aside(out, stage, n, steps)?;
        }
        move_in(out, stage, MARKER, steps)
    }
}

/// An entry name of the set's own: no separators, no `.`/`..`.
fn safe(name: &str) -> bool {
    !name.is_empty() && !name.contains('/') && name != "." && name != ".."
}

fn present(p: &Path) -> bool {
    p.symlink_metadata().is_ok()
}

fn move_in(out: &Path, stage: &Path, name: &str, steps: &mut usize) -> std::io::Result<()> {
    let staged = stage.join("new").join(name);
    if !present(&staged) {
        return Ok(());
    }
    set_aside(out, stage, name, steps)?;
    rename(&staged, &out.join(name), steps)
}

fn rename(from: &Path, to: &Path, steps: &mut usize) -> std::io::Result<()> {
    if *steps == 0 {
        return Err(std::io::ErrorKind::Interrupted.into());
    }
    *steps -= 1;
    std::fs::rename(from, to)
}

/// The old entry of this name moves into the staging folder, which is deleted afterwards.
fn set_aside(out: &Path, stage: &Path, name: &str, steps: &mut usize) -> std::io::Result<()> {
    let target = out.join(name);
    if !present(&target) {
        return Ok(());
    }
    let aside = stage.join("old").join(name);
    if present(&aside) {
        remove(&aside)?;
    }
    rename(&target, &aside, steps)
}

fn remove(p: &Path) -> std::io::Result<()> {
    if p.symlink_metadata()?.is_dir() {
        std::fs::remove_dir_all(p)
    } else {
        std::fs::remove_file(p)
    }
}

/// Removes what a set put in its staging folder, then the folder if nothing else is in it.
pub(super) fn clean(stage: &Path) -> std::io::Result<()> {
    for sub in ["new", "old"] {
        let p = stage.join(sub);
        if present(&p) {
            remove(&p)?;
        }
    }
    for f in [JOURNAL.to_string(), format!("{JOURNAL}.tmp")] {
        let _ = std::fs::remove_file(stage.join(f));
    }
    if !present(stage) {
        return Ok(());
    }
    std::fs::remove_dir(stage).map_err(|_| {
        let names: Vec<String> = std::fs::read_dir(stage)
            .map(|d| {
                d.flatten()
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .collect()
            })
            .unwrap_or_default();
        std::io::Error::other(format!(
            "kept: it holds entries no run wrote ({})",
            names.join(", ")
        ))
    })
}

/// A staging folder of this set's layout: its journalled commit finished, or its unfinished set dropped.
pub(super) fn one(out: &Path, stage: &Path) {
    if !present(stage) {
        return;
    }
    if let Some(journal) = Journal::read(stage) {
        if let Err(e) = journal.roll_forward(out, stage) {
            eprintln!(
                "warning: {}: could not finish an interrupted run's set ({e}); left as it is",
                stage.display()
            );
            return;
        }
    }
    if let Err(e) = clean(stage) {
        eprintln!("warning: {}: {e}", stage.display());
    }
}

/// Every staging folder in or beside `out` whose process is gone.
pub(super) fn stale(out: &Path) {
    for dir in owned_by_dead(out, STAGE_PREFIX) {
        one(out, &dir);
    }
    // Folders staged beside `out` by earlier versions (`.NAME.partial-PID`) could hold user entries.
    if let (Some(parent), Some(name)) = (out.parent(), out.file_name()) {
        for dir in owned_by_dead(parent, &format!(".{}.partial-", name.to_string_lossy())) {
            beside(out, &dir);
        }
    }
}

fn owned_by_dead(dir: &Path, prefix: &str) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let proc_mounted = Path::new("/proc/self").exists();
    entries
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let pid = name.strip_prefix(prefix)?.parse::<u32>().ok()?;
            let alive = !proc_mounted || Path::new(&format!("/proc/{pid}")).exists();
            (!alive).then(|| e.path())
        })
        .collect()
}

/// An earlier version's staging folder: the set it lists goes; every other entry (a user's, carried
/// over by that version) moves back into `out`, or the folder is kept if `out` has that name now.
fn beside(out: &Path, side: &Path) {
    // That version wrote the marker before it carried anything over: without one, all is the set's.
    let Ok(marker) = std::fs::read_to_string(side.join(MARKER)) else {
        let _ = std::fs::remove_dir_all(side);
        return;
    };
    let listed: Vec<String> = marker.lines().map(str::to_string).collect();
    let Ok(entries) = std::fs::read_dir(side) else {
        return;
    };
    let mut kept = Vec::new();
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name == MARKER || listed.contains(&name) {
            continue;
        }
        let back = out.join(&name);
        if present(&back) || std::fs::rename(e.path(), &back).is_err() {
            kept.push(name);
        }
    }
    if kept.is_empty() {
        let _ = std::fs::remove_dir_all(side);
    } else {
        eprintln!(
            "warning: {} holds {} that an interrupted run of an earlier version carried out of {}, and {} has those names now: kept, move what you need by hand",
            side.display(),
            kept.join(", "),
            out.display(),
            out.display()
        );
    }
}
