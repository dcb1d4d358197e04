//! Output folders are written as a set. Every file of a run goes into a hidden staging folder inside
//! `--out` (`.penumbra-stage-PID/new/`); at the end the set's entries are moved into `--out` one by
//! one, each old entry of the same name set aside first, and the old set's other entries go. The
//! folder itself is never moved or replaced, so it may be the current folder (a Slurm job's
//! `--chdir`), and entries the set did not write (a user's notes, `shards/`, job logs) stay where
//! they are through any interrupt: nothing of theirs is ever moved.
//!
//! The moves are journalled: before the first one, the staging folder gets `commit`, naming every
//! entry. A run that finds a killed run's staging folder finishes that commit from the journal (or,
//! without one, drops the unfinished set) before it does anything else (`recover`). So an
//! interrupt leaves the old set, or the new one once its commit began, and never a lost file.
//!
//! SIGINT and SIGTERM (`crate::interrupt`, in the binary) wait for a commit under way to finish;
//! before the commit, they remove the staging folder. Only SIGKILL or a crash leaves work for the
//! next run.
//!
//! A set lists its entries in `.penumbra-set`, written last.

mod recover;
#[cfg(test)]
mod tests;

use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The file naming a set's entries, one per line.
pub const MARKER: &str = ".penumbra-set";
/// Staging folders inside `--out` are named this plus the writing process's id.
const STAGE_PREFIX: &str = ".penumbra-stage-";
/// The journal of a commit in progress, inside the staging folder.
const JOURNAL: &str = "commit";
/// Longest file-name component Linux file systems take (NAME_MAX).
const NAME_MAX: usize = 255;

/// Checks an output folder before any work: it must be a folder (or creatable as one) that this
/// process can write in, every entry of the old set must be movable, and the current folder must not
/// lie inside an entry the set will replace.
pub fn check(out: &Path) -> Result<()> {
    let shown = out.display().to_string();
    let param = |what: String| Error::param(format!("--out {shown}: {what}"));
    if out.exists() && !out.is_dir() {
        return Err(param(
            "is a file, not a folder: give a folder for the output set".into(),
        ));
    }
    let abs = std::path::absolute(out).map_err(|e| param(e.to_string()))?;
    if abs.parent().is_none() {
        return Err(param(
            "the root folder cannot hold an output set: name a folder inside it".into(),
        ));
    }
    // The nearest folder that exists must be a folder we can write in; the names below it must fit.
    let mut existing = abs.as_path();
    while !existing.exists() {
        let name = existing.file_name().map(|n| n.len()).unwrap_or(0);
        if name > NAME_MAX {
            return Err(param(format!("a folder name of {name} bytes is longer than the file system's limit of {NAME_MAX}")));
        }
        existing = existing.parent().unwrap_or(Path::new("/"));
    }
    if !existing.is_dir() {
        return Err(param(format!(
            "{} is a file, not a folder",
            existing.display()
        )));
    }
    let probe = existing.join(format!(".penumbra-probe-{}", std::process::id()));
    std::fs::create_dir(&probe)
        .map_err(|e| param(format!("cannot write in {}: {e}", existing.display())))?;
    let _ = std::fs::remove_dir(&probe);
    if existing == abs {
        let cwd = std::env::current_dir()
            .ok()
            .and_then(|c| c.canonicalize().ok());
        for name in old_entries(&abs) {
            let entry = abs.join(&name);
            let Ok(meta) = entry.symlink_metadata() else {
                continue;
            };
            if let (Some(cwd), Ok(canon)) = (&cwd, entry.canonicalize()) {
                if meta.is_dir() && cwd.starts_with(&canon) {
                    return Err(param(format!("the current folder is inside {name}, which the new set replaces: run from elsewhere")));
                }
            }
            // Moving a folder to another parent rewrites its `..`, which needs write permission on it.
            if meta.is_dir() && !writable(&entry) {
                return Err(param(format!("{name} (written by an earlier run) is not writable, so it cannot be replaced: make it writable or give another --out")));
            }
        }
    }
    Ok(())
}

/// Refuses a run whose input lies inside the set it replaces: an entry the old set in `out` wrote
/// (or a file inside one) goes when the new set is committed, so the run would delete its own
/// input (`calibrate --out` the estimate's folder lost `estimate.jsonl`, exit 0). `inputs` are
/// (flag, path) pairs; the message names both the input and `--out`.
pub fn check_inputs(out: &Path, inputs: &[(&str, &Path)]) -> Result<()> {
    let Ok(dir) = out.canonicalize() else {
        return Ok(());
    };
    for name in old_entries(&dir) {
        let Ok(entry) = dir.join(&name).canonicalize() else {
            continue;
        };
        for (flag, input) in inputs {
            let Ok(given) = input.canonicalize() else {
                continue;
            };
            if given == entry || given.starts_with(&entry) {
                return Err(Error::param(format!(
                    "{flag} {}: lies inside the set --out {} replaces (its entry {name}, written by an earlier run, goes when the new set is written): the run would delete its own input; give another --out",
                    input.display(),
                    out.display()
                )));
            }
        }
    }
    Ok(())
}

/// A set being written; dropped without `commit`, it removes its staging folder (and `--out`, if this
/// set created it and it is still empty).
pub struct OutputSet {
    out: PathBuf,
    stage: PathBuf,
    new: PathBuf,
    created_out: bool,
    committed: bool,
    /// Removes the staging folder if a signal ends the process before the commit.
    on_signal: Option<crate::interrupt::Registered>,
}

impl OutputSet {
    /// Checks `out`, finishes or drops what killed runs left in it, and opens a fresh staging folder.
    pub fn begin(out: &Path) -> Result<Self> {
        check(out)?;
        let abs = std::path::absolute(out).map_err(|e| Error::io(out, e))?;
        let created_out = !abs.exists();
        std::fs::create_dir_all(&abs).map_err(|e| Error::io(out, e))?;
        recover::stale(&abs);
        let stage = abs.join(format!("{STAGE_PREFIX}{}", std::process::id()));
        recover::one(&abs, &stage);
        // Registered before the folder exists, so no signal can leave it behind.
        let on_signal = {
            let (stage, abs) = (stage.clone(), abs.clone());
            crate::interrupt::on_signal(move || drop_unfinished(&stage, &abs, created_out))
        };
        // Made under the commit guard, as every write into the folder is: a signal's clean-up never
        // runs while the folder is being made or written, and no write starts once it has run.
        let made = {
            let _writing = crate::interrupt::critical();
            std::fs::create_dir(&stage).and_then(|_| std::fs::create_dir(stage.join("new")))
        };
        let set = Self {
            out: out.to_path_buf(),
            new: stage.join("new"),
            stage,
            created_out,
            committed: false,
            on_signal: Some(on_signal),
        };
        made.map_err(|e| Error::io(&set.stage, e))?;
        Ok(set)
    }

    /// Where the set is written (or through `write`); its entries move into `out` at `commit`.
    pub fn path(&self) -> &Path {
        &self.new
    }

    /// The folder the set will be: for messages.
    pub fn out(&self) -> &Path {
        &self.out
    }

    /// Held while files are written into [`path`](Self::path) other than by [`write`](Self::write)
    /// (a report rendered into the set): a signal waits for the writes to end, then removes the
    /// staging folder, and any write after that waits for the process to end. Without it a signal
    /// while the set was written could leave `new/…` behind (the writer recreated the folders the
    /// clean-up had removed).
    pub fn writing(&self) -> crate::interrupt::Critical {
        crate::interrupt::critical()
    }

    /// Writes one file of the set (`name` may hold sub-folders, e.g. `charts/x.svg`).
    pub fn write(&self, name: &str, bytes: &[u8]) -> Result<PathBuf> {
        let _writing = self.writing();
        let path = self.new.join(name);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(&self.out.join(name), e))?;
        }
        std::fs::write(&path, bytes).map_err(|e| Error::io(&self.out.join(name), e))?;
        Ok(self.out.join(name))
    }

    /// Moves the new set in: the journal first, then each entry, then the marker; the old set's
    /// other entries go. Entries the old set did not write are never touched.
    pub fn commit(mut self) -> Result<()> {
        // A signal from here on waits for the moves to finish (or to fail and leave the journal).
        let _moving = crate::interrupt::critical();
        let journal = self.journal()?;
        self.committed = true;
        self.on_signal = None;
        journal
            .roll_forward(self.folder(), &self.stage)
            .map_err(|e| {
                Error::io(
                    &self.out,
                    format!(
                        "{e}; the next run into this folder finishes the move from {}",
                        self.stage.display()
                    ),
                )
            })?;
        // The new set is in place: debris left here is only worth a warning, not a failed run.
        if let Err(e) = recover::clean(&self.stage) {
            eprintln!("warning: {}: {e}", self.stage.display());
        }
        Ok(())
    }

    /// Writes the new set's marker and the journal; from here on the commit is decided.
    fn journal(&self) -> Result<recover::Journal> {
        let mut entries: Vec<String> = read_names(&self.new)?
            .into_iter()
            .filter(|n| n != MARKER)
            .collect();
        entries.sort();
        std::fs::write(
            self.new.join(MARKER),
            entries.iter().map(|e| format!("{e}\n")).collect::<String>(),
        )
        .map_err(|e| Error::io(&self.out.join(MARKER), e))?;
        let gone: Vec<String> = old_entries(self.folder())
            .into_iter()
            .filter(|n| !entries.contains(n))
            .collect();
        let journal = recover::Journal { new: entries, gone };
        journal.write(&self.stage)?;
        Ok(journal)
    }

    /// `out` as an absolute path: the staging folder's parent.
    fn folder(&self) -> &Path {
        self.stage.parent().expect("the stage lies inside out")
    }
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        if !self.committed {
            drop_unfinished(&self.stage, self.folder(), self.created_out);
        }
    }
}

/// A set that will not be committed: its staging folder goes, and `out` if this set created it
/// and it is empty again.
fn drop_unfinished(stage: &Path, out: &Path, created_out: bool) {
    let _ = recover::clean(stage);
    if created_out {
        let _ = std::fs::remove_dir(out);
    }
}

/// The entries the set in `dir` wrote, from its marker (none without one).
fn old_entries(dir: &Path) -> Vec<String> {
    std::fs::read_to_string(dir.join(MARKER))
        .map(|t| {
            t.lines()
                .filter(|l| !l.is_empty() && !l.contains('/') && *l != ".." && *l != ".")
                .map(str::to_string)
                .collect()
        })
        .unwrap_or_default()
}

fn read_names(dir: &Path) -> Result<Vec<String>> {
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    Ok(entries
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect())
}

fn writable(path: &Path) -> bool {
    use std::os::unix::ffi::OsStrExt;
    let Ok(c) = std::ffi::CString::new(path.as_os_str().as_bytes()) else {
        return false;
    };
    // SAFETY: a valid NUL-terminated path.
    unsafe { libc::access(c.as_ptr(), libc::W_OK) == 0 }
}
