//! Opening mesh files: gzip is recognised by its magic bytes, not by the file name. Only regular
//! files are opened, and no more than the mesh-file cap is read (decompressed, for gzip).

use std::io::{self, BufRead, BufReader, Read};
use std::path::Path;

use flate2::bufread::MultiGzDecoder;

use super::error::{AssetError, Result};

const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

use penumbra::research::scene::mesh_input::open_regular;
pub use penumbra::research::scene::mesh_input::{
    max_mesh_bytes, set_max_mesh_mib, DEFAULT_MAX_MESH_MIB,
};

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
        Box::new(BufReader::new(Capped {
            inner,
            left: max,
            max,
            what: "decompresses to",
        }))
    } else {
        Box::new(BufReader::new(Capped {
            inner: file,
            left: max,
            max,
            what: "holds",
        }))
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
