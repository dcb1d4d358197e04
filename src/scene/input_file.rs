//! Reading an input file whose kind and size are not trusted: a scene, a rows file
//! (`estimate.jsonl`, `results.jsonl`, a results folder's CSV), a cache entry. A regular file is
//! read up to a cap; a pipe (`--scene <(cat f)`, a FIFO) is read up to the same cap, with a word on
//! stderr while it has no writer; a device (a link to `/dev/zero`), a socket or a folder is refused
//! on its metadata, never opened. Before, `/dev/zero` was read until memory ran out and a FIFO with
//! no writer blocked with no word (docs/robustness.md, "Bad input").

use std::io::Read;
use std::path::Path;
use std::time::Duration;

/// How a size reads in messages: MiB with one decimal, and the exact bytes.
pub(crate) fn show_size(bytes: u64) -> String {
    format!(
        "{:.1} MiB ({bytes} bytes)",
        bytes as f64 / (1u64 << 20) as f64
    )
}

/// The cap on a text input (a scene file, a rows file): far above any the tool writes (a
/// 10,000-row results.jsonl is about 30 MiB) and far below a machine's memory.
pub const TEXT_CAP: u64 = 256 << 20;

/// How long a pipe may stay silent before the run says what it waits for.
const QUIET: Duration = Duration::from_secs(1);

/// `path` as messages show it: with its target when it is a link.
pub(crate) fn shown(path: &Path) -> String {
    match std::fs::canonicalize(path) {
        Ok(target) if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) => {
            format!("{} (a link to {})", path.display(), target.display())
        }
        _ => path.display().to_string(),
    }
}

/// What a file that is not regular is, in words.
pub fn kind(t: &std::fs::FileType) -> &'static str {
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

fn is_pipe(t: &std::fs::FileType) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        t.is_fifo()
    }
    #[cfg(not(unix))]
    {
        let _ = t;
        false
    }
}

/// The bytes of `path`, at most `cap` of them. `Err` is the reason in words that follow the
/// file's name in the caller's message ("cannot read: …"); `cap_name` names the cap there
/// ("the 256 MiB cap on scene files").
pub fn read_capped(path: &Path, cap: u64, cap_name: &str) -> Result<Vec<u8>, String> {
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    let t = meta.file_type();
    if meta.is_file() {
        if meta.len() > cap {
            return Err(format!(
                "{} is {}, over {cap_name}",
                shown(path),
                show_size(meta.len())
            ));
        }
        let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
        return read_to_cap(file, path, cap, cap_name);
    }
    if !is_pipe(&t) {
        return Err(format!(
            "{} is {}, not a regular file or a pipe",
            shown(path),
            kind(&t)
        ));
    }
    // Opening a FIFO blocks until a writer opens it, and reading blocks until it writes: the read
    // runs on a thread, and the run says what it waits for once the pipe has been quiet a while.
    let (owned, named) = (path.to_path_buf(), cap_name.to_string());
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let r = std::fs::File::open(&owned)
            .map_err(|e| e.to_string())
            .and_then(|f| read_to_cap(f, &owned, cap, &named));
        let _ = tx.send(r);
    });
    match rx.recv_timeout(QUIET) {
        Ok(r) => r,
        Err(_) => {
            crate::progress::notice(&format!(
                "waiting for {} ({}) to be written and closed; stop with Ctrl-C",
                path.display(),
                kind(&t)
            ));
            rx.recv().map_err(|e| e.to_string())?
        }
    }
}

/// Reads `file` to its end, refusing more than `cap` bytes (a file that grows while read).
fn read_to_cap(
    file: std::fs::File,
    path: &Path,
    cap: u64,
    cap_name: &str,
) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    file.take(cap + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > cap {
        return Err(format!(
            "{} holds more than {} (read stopped there), over {cap_name}",
            shown(path),
            show_size(cap)
        ));
    }
    Ok(bytes)
}

/// [`read_capped`] as UTF-8 text.
pub fn read_text(path: &Path, cap: u64, cap_name: &str) -> Result<String, String> {
    String::from_utf8(read_capped(path, cap, cap_name)?)
        .map_err(|_| "stream did not contain valid UTF-8".to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_are_refused_pipes_and_files_are_capped() {
        let dir = tempfile::tempdir().unwrap();
        let link = dir.path().join("zero.toml");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        let e = read_capped(&link, TEXT_CAP, "the cap on scene files").unwrap_err();
        assert!(
            e.contains("(a link to /dev/zero) is a character device, not a regular file or a pipe"),
            "{e}"
        );
        let file = dir.path().join("f.txt");
        std::fs::write(&file, b"0123456789").unwrap();
        assert_eq!(read_capped(&file, 10, "c").unwrap(), b"0123456789");
        let e = read_capped(&file, 9, "the 9-byte cap").unwrap_err();
        assert!(
            e.ends_with("is 0.0 MiB (10 bytes), over the 9-byte cap"),
            "{e}"
        );
        let e = read_capped(dir.path(), 9, "c").unwrap_err();
        assert!(
            e.ends_with("is a folder, not a regular file or a pipe"),
            "{e}"
        );
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_fifo_is_read_once_written_and_capped() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("p");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        let writer = {
            let fifo = fifo.clone();
            std::thread::spawn(move || {
                std::thread::sleep(Duration::from_millis(100));
                std::fs::write(&fifo, vec![b'x'; 100]).unwrap();
            })
        };
        assert_eq!(read_capped(&fifo, 1000, "c").unwrap().len(), 100);
        writer.join().unwrap();
        let writer = {
            let fifo = fifo.clone();
            // The writer meets a closed reader once the cap is hit: its error is expected.
            std::thread::spawn(move || {
                let _ = std::fs::write(&fifo, vec![b'x'; 100]);
            })
        };
        let e = read_capped(&fifo, 50, "the 50-byte cap").unwrap_err();
        assert!(e.ends_with("over the 50-byte cap"), "{e}");
        writer.join().unwrap();
    }
}
