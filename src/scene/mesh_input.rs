//! Opening mesh files: only regular files are opened, and no more than the mesh-file cap is read.
//! The registry formats (gzip included) are read by the lab's asset layer on top of these checks.

use std::fs::File;
use std::io;
use std::path::Path;
use std::sync::OnceLock;

/// The default cap on a mesh file's size (and a gzip file's decompressed size): far above the
/// largest mesh the registries ship (the 8 MB dragon_vrip.ply.gz, about 32 MB decompressed).
pub const DEFAULT_MAX_MESH_MIB: u64 = 2048;

static RUN_MAX_MESH_MIB: OnceLock<u64> = OnceLock::new();

/// Sets the cap for this run (`--max-mesh-mib`); only the first call counts.
pub fn set_max_mesh_mib(mib: u64) {
    let _ = RUN_MAX_MESH_MIB.set(mib);
}

/// The cap in bytes: `--max-mesh-mib` when given, else the default.
pub fn max_mesh_bytes() -> u64 {
    RUN_MAX_MESH_MIB
        .get()
        .copied()
        .unwrap_or(DEFAULT_MAX_MESH_MIB)
        .saturating_mul(1 << 20)
}

/// Why a mesh file may not be read, in the engine's words; over the cap apart, since each front
/// end says how to raise it.
#[derive(Debug)]
pub(crate) enum Refusal {
    Unreadable(String),
    OverCap { why: String, cap_mib: u64 },
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refusal::Unreadable(why) | Refusal::OverCap { why, .. } => f.write_str(why),
        }
    }
}

/// Why `path` (symlinks followed) may not be read as a mesh: not a regular file, or over `max`
/// bytes. Looks at the metadata only, so a FIFO is never opened (opening one blocks).
pub(crate) fn check_mesh_file(path: &Path, max: u64) -> std::result::Result<(), Refusal> {
    use super::input_file::{kind, show_size, shown};
    // The callers name the file and say "cannot read"; the reason alone, so neither repeats.
    let meta = std::fs::metadata(path).map_err(|e| Refusal::Unreadable(e.to_string()))?;
    if !meta.is_file() {
        return Err(Refusal::Unreadable(format!(
            "{} is {}, not a regular file",
            shown(path),
            kind(&meta.file_type())
        )));
    }
    if meta.len() > max {
        return Err(Refusal::OverCap {
            why: format!(
                "{} is {}, over the {} MiB cap on mesh files",
                shown(path),
                show_size(meta.len()),
                max >> 20
            ),
            cap_mib: max >> 20,
        });
    }
    Ok(())
}

/// Opens a regular file for reading. A FIFO swapped in after the check does not block the open
/// (O_NONBLOCK) and is refused by the check on the opened file.
pub fn open_regular(path: &Path, max: u64) -> io::Result<File> {
    check_mesh_file(path, max).map_err(|r| io::Error::other(r.to_string()))?;
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path)?;
    if !file.metadata()?.is_file() {
        return Err(io::Error::other("not a regular file"));
    }
    Ok(file)
}
