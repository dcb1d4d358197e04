//! Opening mesh files: gzip is recognised by its magic bytes, not by the file name.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use flate2::bufread::MultiGzDecoder;

use super::error::{AssetError, Result};

const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

/// A buffered reader over the file's content, decompressed when it is gzip.
pub(crate) fn open(path: &Path) -> Result<Box<dyn BufRead>> {
    let read_error = |source| AssetError::Read {
        file: path.to_path_buf(),
        source,
    };
    let mut file = BufReader::new(File::open(path).map_err(read_error)?);
    let is_gzip = file
        .fill_buf()
        .map_err(read_error)?
        .starts_with(&GZIP_MAGIC);
    Ok(if is_gzip {
        Box::new(BufReader::new(MultiGzDecoder::new(file)))
    } else {
        Box::new(file)
    })
}

pub(crate) fn read_text(path: &Path) -> Result<String> {
    let mut bytes = Vec::new();
    open(path)?
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
