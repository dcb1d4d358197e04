//! `penumbra assets fetch`: the fetch with its progress printed, and an optional check that
//! each fetched mesh loads with the counts data.md records.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::cache::default_cache_dir;
use super::download::Origin;
use super::error::{AssetError, Result};
use super::fetch::{fetch_groups, Action, FetchReport, Progress};
use super::manifest::{AssetFile, Group, MeshCounts};

#[derive(Debug, Clone)]
pub struct FetchCommand {
    pub groups: Vec<Group>,
    /// `None`: [`default_cache_dir`].
    pub cache_dir: Option<PathBuf>,
    /// Load every fetched mesh and compare its vertex/triangle counts with the manifest.
    pub check: bool,
}

impl Default for FetchCommand {
    fn default() -> Self {
        FetchCommand {
            groups: Group::DEFAULT.to_vec(),
            cache_dir: None,
            check: false,
        }
    }
}

impl FetchCommand {
    /// Progress goes to `out` line by line; a failed write to `out` does not stop the fetch.
    pub fn run(&self, out: &mut dyn Write) -> Result<FetchReport> {
        let cache_dir = match &self.cache_dir {
            Some(dir) => dir.clone(),
            None => default_cache_dir()?,
        };
        let groups: Vec<&str> = self.groups.iter().map(|g| g.name()).collect();
        let _ = writeln!(
            out,
            "cache {} (groups: {})",
            cache_dir.display(),
            groups.join(", ")
        );
        // Counted from the events, so a run that fails still says what it did.
        let mut tally = Tally::default();
        let fetched = fetch_groups(&cache_dir, &self.groups, &mut |event| {
            tally.count(&event);
            match &event {
                // Retries go to stderr as they happen: a slow or absent network is not silent.
                // A failure is in the run's one error line at the end.
                Progress::Retrying { .. } => eprintln!("warning: {}", describe(&event)),
                _ => {
                    let _ = writeln!(out, "{}", describe(&event));
                }
            }
        });
        // Said whenever the fetch got as far as the archives, failed ones included.
        if matches!(fetched, Ok(_) | Err(AssetError::NotFetched { .. })) {
            let _ = writeln!(out, "{}", tally.summary());
        }
        let report = fetched?;
        if self.check {
            for fetched in &report.files {
                if let Some(expected) = fetched.file.mesh {
                    check_counts(fetched.file, &fetched.path, expected, out)?;
                }
            }
        }
        Ok(report)
    }
}

/// What a fetch did, by archive and by file.
#[derive(Default)]
struct Tally {
    installed: usize,
    replaced: usize,
    present: usize,
    downloaded: usize,
    downloaded_bytes: u64,
    from_npm_cache: usize,
    failed: usize,
}

impl Tally {
    fn count(&mut self, event: &Progress) {
        match event {
            Progress::Present { .. } => self.present += 1,
            Progress::Installed {
                action: Action::Replaced,
                ..
            } => self.replaced += 1,
            Progress::Installed { .. } => self.installed += 1,
            Progress::Downloaded {
                origin: Origin::NpmCache,
                ..
            } => self.from_npm_cache += 1,
            Progress::Downloaded { bytes, .. } => {
                self.downloaded += 1;
                self.downloaded_bytes += bytes;
            }
            Progress::Failed { .. } => self.failed += 1,
            Progress::Downloading { .. }
            | Progress::Retrying { .. }
            | Progress::Generating { .. } => {}
        }
    }

    fn summary(&self) -> String {
        format!(
            "{} files verified ({} installed, {} replaced, {} already present); archives: {} downloaded ({}), {} from npm's cache (not downloaded), {} failed",
            self.installed + self.replaced + self.present,
            self.installed,
            self.replaced,
            self.present,
            self.downloaded,
            bytes(self.downloaded_bytes),
            self.from_npm_cache,
            self.failed,
        )
    }
}

fn describe(event: &Progress) -> String {
    match event {
        Progress::Present { file, .. } => {
            format!("present    {:<32} {:>12}", file.dest, bytes(file.size))
        }
        Progress::Downloading { package } => format!("download   {package}"),
        Progress::Downloaded {
            package,
            bytes: n,
            origin,
        } => {
            format!(
                "verified   {} {} archive{}, sha256 {}",
                bytes(*n),
                package.name,
                if *origin == Origin::NpmCache {
                    " (from npm's cache)"
                } else {
                    ""
                },
                &package.sha256[..16]
            )
        }
        Progress::Retrying {
            package,
            attempt,
            attempts,
            reason,
        } => format!("{package}: {reason}; retrying (attempt {attempt} of {attempts})"),
        Progress::Failed { package, reason } => format!("failed     {package}: {reason}"),
        Progress::Generating { file } => format!("generating {} with node", file.dest),
        Progress::Installed { file, action, .. } => {
            let verb = if *action == Action::Replaced {
                "replaced "
            } else {
                "installed"
            };
            format!(
                "{verb}  {:<32} {:>12}  sha256 {}",
                file.dest,
                bytes(file.size),
                &file.sha256[..16]
            )
        }
    }
}

fn check_counts(
    file: &AssetFile,
    path: &Path,
    expected: MeshCounts,
    out: &mut dyn Write,
) -> Result<()> {
    let found = if file.dest.ends_with(".obj") {
        obj_counts(path)?
    } else {
        let mesh = super::load_mesh(path)?;
        MeshCounts {
            vertices: mesh.vertex_count(),
            triangles: mesh.triangle_count(),
        }
    };
    let show = |c: MeshCounts| format!("{} vertices / {} triangles", c.vertices, c.triangles);
    if found != expected {
        return Err(AssetError::CountMismatch {
            file: path.into(),
            expected: show(expected),
            found: show(found),
        });
    }
    let _ = writeln!(out, "loaded     {:<32} {}", file.dest, show(found));
    Ok(())
}

/// The OBJ export writes one `v` line per vertex and triangles as `f` lines; count, not parse.
fn obj_counts(path: &Path) -> Result<MeshCounts> {
    let text = super::input::read_text(path)?;
    let lines = |prefix| text.lines().filter(|l| l.starts_with(prefix)).count();
    Ok(MeshCounts {
        vertices: lines("v "),
        triangles: lines("f "),
    })
}

fn bytes(n: u64) -> String {
    let digits = n.to_string();
    let mut grouped = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            grouped.push(',');
        }
        grouped.push(c);
    }
    grouped + " B"
}

/// The command that fetches `groups` (the groups a scene's missing assets belong to); `None`
/// when nothing is missing.
pub fn fetch_command(groups: &[String]) -> Option<String> {
    (!groups.is_empty()).then(|| {
        let flags: Vec<String> = groups.iter().map(|g| format!("--group {g}")).collect();
        format!("penumbra assets fetch {}", flags.join(" "))
    })
}
