//! sha256 of files, as lowercase hex, and the check against a pinned digest.

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

use sha2::{Digest, Sha256};

use super::error::{AssetError, Result};

/// Digest and size of a file.
pub(crate) fn sha256_file(path: &Path) -> io::Result<(String, u64)> {
    let mut file = File::open(path)?;
    let mut hasher = Sha256::new();
    let mut buffer = vec![0u8; 1 << 16];
    let mut size = 0u64;
    loop {
        let n = file.read(&mut buffer)?;
        if n == 0 {
            break;
        }
        hasher.update(&buffer[..n]);
        size += n as u64;
    }
    let hex = hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    Ok((hex, size))
}

/// Ok when `path` holds exactly the pinned content; the error names file, expected and got.
pub(crate) fn verify(path: &Path, expected: &str, hint: &str) -> Result<u64> {
    let (got, size) = sha256_file(path).map_err(|source| AssetError::Read {
        file: path.to_path_buf(),
        source,
    })?;
    if got != expected {
        return Err(AssetError::DigestMismatch {
            file: path.to_path_buf(),
            expected: expected.to_string(),
            got,
            hint: hint.to_string(),
        });
    }
    Ok(size)
}

/// True when `path` exists and matches; any read problem just means "fetch it again".
pub(crate) fn is_verified(path: &Path, expected: &str, size: u64) -> bool {
    let same_size = std::fs::metadata(path).is_ok_and(|m| m.len() == size);
    same_size && sha256_file(path).is_ok_and(|(got, _)| got == expected)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_digest_and_mismatch_message() {
        let dir = std::env::temp_dir().join(format!("penumbra-digest-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("abc.txt");
        std::fs::write(&path, "abc").unwrap();
        let abc = "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
        assert_eq!(verify(&path, abc, "").unwrap(), 3);
        assert!(is_verified(&path, abc, 3));
        let wrong = "0".repeat(64);
        let message = verify(&path, &wrong, "").unwrap_err().to_string();
        assert_eq!(
            message,
            format!(
                "{}: sha256 mismatch: expected {wrong}, got {abc}",
                path.display()
            )
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
