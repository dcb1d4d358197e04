//! Output folders are written as a set: every file goes into a hidden staging folder beside `--out`,
//! which is swapped with `--out` in one step at the end. An interrupt or a failed write leaves the
//! old set untouched, and a finished run leaves exactly the new set: files of an earlier set that
//! this one does not write (an adaptive run's comparison_map.png under a later regular run) go.
//!
//! A set lists its entries in `.penumbra-set`. Entries of the folder that the old set did not write
//! (a user's notes, `penumbra reference`'s `reference/` inside `penumbra-out/`) are carried over.

use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The file naming a set's entries, one per line.
pub const MARKER: &str = ".penumbra-set";

/// Checks an output folder before any work: it must not be a file, the current folder or one that
/// holds it, and the folder beside which the set is staged must be writable.
pub fn check(out: &Path) -> Result<()> {
    let shown = out.display().to_string();
    let param = |what: String| Error::Param(format!("--out {shown}: {what}"));
    if out.exists() && !out.is_dir() {
        return Err(param("is a file, not a folder: give a folder for the output set".into()));
    }
    let abs = std::path::absolute(out).map_err(|e| param(e.to_string()))?;
    let Some(parent) = abs.parent() else {
        return Err(param("the root folder cannot hold an output set: name a folder inside it".into()));
    };
    if let Ok(cwd) = std::env::current_dir() {
        let abs_canon = abs.canonicalize().unwrap_or_else(|_| abs.clone());
        if cwd.starts_with(&abs_canon) {
            return Err(param("is the current folder or holds it: the set replaces the whole folder, so name a sub-folder".into()));
        }
    }
    // The nearest folder that exists must be a folder we can write in.
    let mut existing = parent;
    while !existing.exists() {
        existing = existing.parent().unwrap_or(Path::new("/"));
    }
    if !existing.is_dir() {
        return Err(param(format!("{} is a file, not a folder", existing.display())));
    }
    let probe = existing.join(format!(".penumbra-probe-{}", std::process::id()));
    std::fs::create_dir(&probe).map_err(|e| param(format!("cannot write in {}: {e}", existing.display())))?;
    let _ = std::fs::remove_dir(&probe);
    Ok(())
}

/// A set being written; dropped without `commit`, it removes its staging folder.
pub struct OutputSet {
    out: PathBuf,
    stage: PathBuf,
    committed: bool,
}

fn stage_prefix(out: &Path) -> String {
    format!(".{}.partial-", out.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default())
}

/// Staging folders left by runs that were killed (their process is gone): removed.
fn sweep_stale(parent: &Path, prefix: &str) {
    let Ok(entries) = std::fs::read_dir(parent) else { return };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(pid) = name.strip_prefix(prefix).and_then(|p| p.parse::<u32>().ok()) else { continue };
        let alive = Path::new(&format!("/proc/{pid}")).exists() || !Path::new("/proc/self").exists();
        if !alive {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

impl OutputSet {
    /// Checks `out` and opens a fresh staging folder beside it.
    pub fn begin(out: &Path) -> Result<Self> {
        check(out)?;
        let abs = std::path::absolute(out).map_err(|e| Error::io(out, e))?;
        let parent = abs.parent().expect("checked: has a parent").to_path_buf();
        std::fs::create_dir_all(&parent).map_err(|e| Error::io(&parent, e))?;
        let prefix = stage_prefix(&abs);
        sweep_stale(&parent, &prefix);
        let stage = parent.join(format!("{prefix}{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&stage);
        std::fs::create_dir(&stage).map_err(|e| Error::io(&stage, e))?;
        Ok(Self { out: out.to_path_buf(), stage, committed: false })
    }

    /// The staging folder: write here (or through `write`); it becomes `out` at `commit`.
    pub fn path(&self) -> &Path {
        &self.stage
    }

    /// The folder the set will be: for messages.
    pub fn out(&self) -> &Path {
        &self.out
    }

    /// Writes one file of the set (`name` may hold sub-folders, e.g. `charts/x.svg`).
    pub fn write(&self, name: &str, bytes: &[u8]) -> Result<PathBuf> {
        let path = self.stage.join(name);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(&self.out.join(name), e))?;
        }
        std::fs::write(&path, bytes).map_err(|e| Error::io(&self.out.join(name), e))?;
        Ok(self.out.join(name))
    }

    /// Swaps the new set in: the old set's entries go, other entries of the folder are carried over.
    pub fn commit(mut self) -> Result<()> {
        let mut entries: Vec<String> = read_names(&self.stage)?.into_iter().filter(|n| n != MARKER).collect();
        entries.sort();
        std::fs::write(self.stage.join(MARKER), entries.join("\n") + "\n").map_err(|e| Error::io(&self.out.join(MARKER), e))?;
        if !self.out.exists() {
            std::fs::rename(&self.stage, &self.out).map_err(|e| Error::io(&self.out, e))?;
            self.committed = true;
            return Ok(());
        }
        let old_set: Vec<String> = std::fs::read_to_string(self.out.join(MARKER))
            .map(|t| t.lines().map(str::to_string).collect())
            .unwrap_or_default();
        // Entries the old set did not write and the new one does not replace: carried over.
        let carried: Vec<String> = read_names(&self.out)?
            .into_iter()
            .filter(|n| n != MARKER && !old_set.contains(n) && !entries.contains(n))
            .collect();
        let mut moved = Vec::new();
        for name in &carried {
            if let Err(e) = std::fs::rename(self.out.join(name), self.stage.join(name)) {
                for back in &moved {
                    let _ = std::fs::rename(self.stage.join(back), self.out.join(back));
                }
                return Err(Error::io(&self.out.join(name), e));
            }
            moved.push(name.clone());
        }
        if let Err(e) = exchange(&self.stage, &self.out) {
            for back in &moved {
                let _ = std::fs::rename(self.stage.join(back), self.out.join(back));
            }
            return Err(Error::io(&self.out, e));
        }
        // The staging path now holds the old set.
        self.committed = true;
        std::fs::remove_dir_all(&self.stage).map_err(|e| Error::io(&self.stage, e))
    }
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.stage);
        }
    }
}

fn read_names(dir: &Path) -> Result<Vec<String>> {
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    Ok(entries.flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect())
}

/// Swaps two folders in one step where the system can (Linux: renameat2 with RENAME_EXCHANGE).
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
    use std::ffi::CString;
    use std::os::unix::ffi::OsStrExt;
    let ca = CString::new(a.as_os_str().as_bytes())?;
    let cb = CString::new(b.as_os_str().as_bytes())?;
    // SAFETY: two valid NUL-terminated paths, relative to the current folder (AT_FDCWD).
    let rc = unsafe { libc::syscall(libc::SYS_renameat2, libc::AT_FDCWD, ca.as_ptr(), libc::AT_FDCWD, cb.as_ptr(), libc::RENAME_EXCHANGE) };
    if rc == 0 {
        return Ok(());
    }
    let err = std::io::Error::last_os_error();
    // Filesystems without exchange support: the two-step swap below.
    if matches!(err.raw_os_error(), Some(libc::EINVAL) | Some(libc::ENOSYS)) {
        return exchange_in_two_steps(a, b);
    }
    Err(err)
}

#[cfg(not(target_os = "linux"))]
fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
    exchange_in_two_steps(a, b)
}

/// b → a side name, a → b, side name → a: an interrupt between the steps leaves the old set beside.
fn exchange_in_two_steps(a: &Path, b: &Path) -> std::io::Result<()> {
    let side = a.with_extension("old");
    std::fs::rename(b, &side)?;
    if let Err(e) = std::fs::rename(a, b) {
        let _ = std::fs::rename(&side, b);
        return Err(e);
    }
    std::fs::rename(&side, a)
}
