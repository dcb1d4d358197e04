//! Getting the manifest's files into the cache: download, verify, extract, verify, rename.
//!
//! Nothing unverified ever sits at a destination path: everything is written into a work
//! folder inside the cache (same file system, so the final rename is atomic), checked against
//! its pinned digest, then renamed into place. The work folder is removed on every exit path.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::digest::{is_verified, verify};
use super::error::{AssetError, Result, io_at};
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
    Downloaded {
        package: &'static Package,
        bytes: u64,
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
    /// Archives downloaded in this run, with their verified sizes.
    pub downloads: Vec<(&'static Package, u64)>,
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

    std::fs::create_dir_all(cache_dir).map_err(io_at(cache_dir))?;
    let work = WorkDir::create(cache_dir)?;
    let mut archives = Archives {
        work: &work.0,
        paths: HashMap::new(),
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
        let archive = archives.get(package, &mut report, progress)?;
        let files: Vec<(&'static AssetFile, &Member)> = todo
            .iter()
            .filter_map(|f| match &f.source {
                Source::Extract { package: p, member } if *p == package => Some((*f, member)),
                _ => None,
            })
            .collect();
        let wanted: Vec<(&Member, PathBuf)> = files
            .iter()
            .map(|(f, member)| (*member, work.0.join(f.dest.replace('/', "__"))))
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
            let inputs = [
                (a, archives.get(a, &mut report, progress)?),
                (b, archives.get(b, &mut report, progress)?),
            ];
            progress(Progress::Generating { file });
            let temp = work.0.join(file.dest.replace('/', "__"));
            let inputs = inputs.each_ref().map(|(p, path)| (*p, path.as_path()));
            tree::generate(preset, inputs, &work.0, &temp)?;
            let installed = install(file, &temp, cache_dir, &tree::mismatch_hint(), progress);
            report.files.push(installed?);
        }
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

/// Downloaded and verified archives of this run, each fetched at most once.
struct Archives<'w> {
    work: &'w Path,
    paths: HashMap<&'static str, PathBuf>,
}

impl Archives<'_> {
    fn get(
        &mut self,
        package: &'static Package,
        report: &mut FetchReport,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<PathBuf> {
        if let Some(path) = self.paths.get(package.name) {
            return Ok(path.clone());
        }
        progress(Progress::Downloading { package });
        let dir = self.work.join(format!("download-{}", self.paths.len()));
        std::fs::create_dir_all(&dir).map_err(io_at(&dir))?;
        let path = tools::download(package, &dir)?;
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
        progress(Progress::Downloaded { package, bytes });
        report.downloads.push((package, bytes));
        self.paths.insert(package.name, path.clone());
        Ok(path)
    }
}

/// `<cache>/.partial-<pid>`: removed when dropped, whether the fetch succeeded or not.
struct WorkDir(PathBuf);

impl WorkDir {
    fn create(cache_dir: &Path) -> Result<Self> {
        let path = cache_dir.join(format!(".partial-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path); // a leftover of a killed run with our pid
        std::fs::create_dir(&path).map_err(io_at(&path))?;
        Ok(WorkDir(path))
    }
}

impl Drop for WorkDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
