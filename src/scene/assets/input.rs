//! Opening mesh files: gzip is recognised by its magic bytes, not by the file name. Only regular
//! files are opened, and no more than the mesh-file cap is read (decompressed, for gzip).

use std::fs::File;
use std::io::{self, BufRead, BufReader, Read};
use std::path::Path;
use std::sync::OnceLock;

use flate2::bufread::MultiGzDecoder;

use super::error::{AssetError, Result};

const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

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
    RUN_MAX_MESH_MIB.get().copied().unwrap_or(DEFAULT_MAX_MESH_MIB).saturating_mul(1 << 20)
}

/// How a size reads in messages: MiB with one decimal, and the exact bytes.
pub(crate) fn show_size(bytes: u64) -> String {
    format!("{:.1} MiB ({bytes} bytes)", bytes as f64 / (1u64 << 20) as f64)
}

/// Why `path` (symlinks followed) may not be read as a mesh: not a regular file, or over `max`
/// bytes. Looks at the metadata only, so a FIFO is never opened (opening one blocks).
pub(crate) fn check_mesh_file(path: &Path, max: u64) -> std::result::Result<(), String> {
    let shown = || match std::fs::canonicalize(path) {
        Ok(target) if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) => {
            format!("{} (a link to {})", path.display(), target.display())
        }
        _ => path.display().to_string(),
    };
    // The callers name the file and say "cannot read"; the reason alone, so neither repeats.
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if !meta.is_file() {
        return Err(format!("{} is {}, not a regular file", shown(), kind(&meta.file_type())));
    }
    if meta.len() > max {
        return Err(format!("{} is {}, over the {} MiB cap on mesh files (raise it with --max-mesh-mib N)", shown(), show_size(meta.len()), max >> 20));
    }
    Ok(())
}

fn kind(t: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a folder"
    } else {
        "not a file"
    }
}

/// Opens a regular file for reading. A FIFO swapped in after the check does not block the open
/// (O_NONBLOCK) and is refused by the check on the opened file.
pub(crate) fn open_regular(path: &Path, max: u64) -> io::Result<File> {
    check_mesh_file(path, max).map_err(io::Error::other)?;
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

/// Reads at most `max` bytes; more is an error, never a silent truncation.
struct Capped<R> {
    inner: R,
    left: u64,
    max: u64,
    what: &'static str,
}

impl<R: Read> Read for Capped<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.left == 0 {
            // At the cap: one more byte means the input is over it.
            return match self.inner.read(&mut [0u8])? {
                0 => Ok(0),
                _ => Err(io::Error::other(format!(
                    "{} more than the {} MiB cap on mesh files (raise it with --max-mesh-mib N)",
                    self.what,
                    self.max >> 20
                ))),
            };
        }
        let n = buf.len().min(self.left.min(usize::MAX as u64) as usize);
        let got = self.inner.read(&mut buf[..n])?;
        self.left -= got as u64;
        Ok(got)
    }
}

/// A buffered reader over the file's content, decompressed when it is gzip; at most `max` bytes
/// (after decompression).
pub(crate) fn open_capped(path: &Path, max: u64) -> Result<Box<dyn BufRead>> {
    let read_error = |source| AssetError::Read {
        file: path.to_path_buf(),
        source,
    };
    let mut file = BufReader::new(open_regular(path, max).map_err(read_error)?);
    let is_gzip = file
        .fill_buf()
        .map_err(read_error)?
        .starts_with(&GZIP_MAGIC);
    Ok(if is_gzip {
        let inner = MultiGzDecoder::new(file);
        Box::new(BufReader::new(Capped { inner, left: max, max, what: "decompresses to" }))
    } else {
        Box::new(BufReader::new(Capped { inner: file, left: max, max, what: "holds" }))
    })
}

pub(crate) fn read_text(path: &Path) -> Result<String> {
    read_text_capped(path, max_mesh_bytes())
}

pub(crate) fn read_text_capped(path: &Path, max: u64) -> Result<String> {
    let mut bytes = Vec::new();
    open_capped(path, max)?
        .read_to_end(&mut bytes)
        .map_err(|source| AssetError::Read {
            file: path.to_path_buf(),
            source,
        })?;
    String::from_utf8(bytes).map_err(|e| AssetError::Invalid {
        file: path.to_path_buf(),
        message: format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
    })
}
