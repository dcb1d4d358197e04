//! On-disk cache of reference images: a ray-traced ground truth costs minutes, the key is cheap.
//!
//! File `<dir>/<key>.vis` (format 2): magic `PNMBREF2`, then little-endian `u32 width`,
//! `u32 height`, `u32 key_len`, the key's UTF-8 bytes, `width·height` `f32` values (row-major),
//! and last the sha256 of every byte before it. A figure is only as good as its reference, so an
//! entry is used only when its digest matches and every value is a visibility (finite, in [0, 1]);
//! anything else is [`Lookup::Damaged`], which the caller traces again (docs/robustness.md).
//! Format 1 (`PNMBREF1`) had no digest: such a file is damaged by definition and traced again.

use super::{RefLight, ReferenceError, ReferenceMode};
use sha2::{Digest, Sha256};
use std::fs;
use std::io::ErrorKind;
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 8] = b"PNMBREF2";
/// The format before digests: never trusted.
const OLD_MAGIC: &[u8; 8] = b"PNMBREF1";
const HEADER: usize = 20;
const DIGEST: usize = 32;

/// FNV-1a 64-bit over the parts, each prefixed by its length so `["ab","c"] != ["a","bc"]`.
/// Returned as 16 lowercase hex digits. Not cryptographic: keys name cache files, nothing more.
pub fn cache_key(parts: &[&[u8]]) -> String {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let mut h = OFFSET;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h ^= b as u64;
            h = h.wrapping_mul(PRIME);
        }
    };
    for part in parts {
        eat(&(part.len() as u64).to_le_bytes());
        eat(part);
    }
    format!("{h:016x}")
}

/// Bump when the tracer's results change (sampling, conventions), so old caches go stale.
pub const REFERENCE_VERSION: u32 = 3;

/// Key of one reference image: `scene` names the geometry and camera (e.g. the scene file's bytes
/// and the resolution), the rest are the tracing inputs.
pub fn reference_key(
    scene: &[u8],
    light: &RefLight,
    mode: &ReferenceMode,
    ray_offset: f32,
) -> String {
    let mut light_bytes = Vec::with_capacity(36);
    for v in [light.center, light.edge_u, light.edge_v] {
        for c in v.to_array() {
            light_bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    cache_key(&[
        b"penumbra-reference",
        &REFERENCE_VERSION.to_le_bytes(),
        scene,
        &light_bytes,
        &mode.key_bytes(),
        &ray_offset.to_le_bytes(),
    ])
}

/// Where the buffer for `key` lives in `dir`.
pub fn cache_path(dir: &Path, key: &str) -> PathBuf {
    dir.join(format!("{key}.vis"))
}

/// The bytes of one cache file: header, key, values and their digest.
pub fn encode(key: &str, width: u32, height: u32, values: &[f32]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(HEADER + key.len() + 4 * values.len() + DIGEST);
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&width.to_le_bytes());
    bytes.extend_from_slice(&height.to_le_bytes());
    bytes.extend_from_slice(&(key.len() as u32).to_le_bytes());
    bytes.extend_from_slice(key.as_bytes());
    for v in values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    let digest = Sha256::digest(&bytes);
    bytes.extend_from_slice(&digest);
    bytes
}

/// Writes the buffer (creating `dir`); written to a temporary name and renamed, so an
/// interrupted run never leaves a truncated file under the real name.
pub fn save_cached(
    dir: &Path,
    key: &str,
    width: u32,
    height: u32,
    values: &[f32],
) -> Result<PathBuf, ReferenceError> {
    let expected = width as usize * height as usize;
    if values.len() != expected {
        return Err(ReferenceError::SizeMismatch {
            expected,
            got: values.len(),
        });
    }
    let path = cache_path(dir, key);
    let failed = |source| ReferenceError::CacheWrite {
        path: path.clone(),
        source,
    };
    fs::create_dir_all(dir).map_err(failed)?;
    let tmp = dir.join(format!("{key}.vis.tmp{}", std::process::id()));
    fs::write(&tmp, encode(key, width, height, values)).map_err(failed)?;
    fs::rename(&tmp, &path).map_err(|e| {
        let _ = fs::remove_file(&tmp);
        failed(e)
    })?;
    Ok(path)
}

/// An exclusive claim on computing one cache entry, shared by every process that uses the
/// folder (shards on one machine, or on many through a shared file system). The claim is an OS
/// lock (`flock`) on `<key>.lock`, which dies with its holder however it ends (a signal, SIGKILL,
/// a crash), so a lock file left behind never blocks anyone: the next run takes it. The file
/// holds the owner's pid and host for the waiting message only. Before, the file's existence was
/// the claim and a dead owner was told by its pid: once the pid belonged to another live process,
/// every run needing the entry waited forever.
pub struct CacheLock {
    path: PathBuf,
    /// Held open: closing it (the drop, or the process ending) releases the lock.
    _file: fs::File,
    /// Removes the lock file if a signal ends the process while the claim is held.
    _on_signal: crate::interrupt::Registered,
}

impl Drop for CacheLock {
    fn drop(&mut self) {
        // Removed while still locked, so a waiter that then locks this file sees it unlinked
        // (`same_file` below) and opens the path afresh.
        let _ = fs::remove_file(&self.path);
    }
}

fn host_name() -> String {
    fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .unwrap_or_else(|_| "unknown-host".into())
}

/// Whether the open `file` is still the one at `path` (not unlinked or replaced by its holder).
fn same_file(file: &fs::File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Takes the lock for `key` in `dir`, waiting while another live process holds it; `waiting`
/// is called once, with the holder's description, if it has to wait.
pub fn lock(
    dir: &Path,
    key: &str,
    waiting: &mut dyn FnMut(&str),
) -> Result<CacheLock, ReferenceError> {
    use std::io::{Seek, Write};
    use std::os::unix::io::AsRawFd;
    fs::create_dir_all(dir)?;
    let path = dir.join(format!("{key}.lock"));
    let mut told = false;
    loop {
        let mut file = fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)?;
        // SAFETY: flock on a descriptor this function owns.
        let locked = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) } == 0;
        let err = std::io::Error::last_os_error();
        if locked || err.raw_os_error() != Some(libc::EWOULDBLOCK) {
            // A file system without locks (ENOLCK) leaves the claim advisory: two runs may then
            // trace the same entry, which costs time, not figures (the entry is renamed in whole).
            if !same_file(&file, &path) {
                continue;
            }
            file.set_len(0)?;
            file.seek(std::io::SeekFrom::Start(0))?;
            writeln!(file, "{} {}", std::process::id(), host_name())?;
            let on_signal = {
                let path = path.clone();
                crate::interrupt::on_signal(move || {
                    let _ = fs::remove_file(&path);
                })
            };
            return Ok(CacheLock {
                path,
                _file: file,
                _on_signal: on_signal,
            });
        }
        if !told {
            waiting(fs::read_to_string(&path).unwrap_or_default().trim());
            told = true;
        }
        drop(file);
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
}

/// One parsed cache file.
#[derive(Debug, PartialEq)]
pub struct CacheEntry {
    pub width: u32,
    pub height: u32,
    pub key: Vec<u8>,
    pub values: Vec<f32>,
}

/// Parses a cache file's bytes; `Err` says what is wrong, in words that follow the file's name.
/// Never panics and allocates no more than the input's size (the fuzz target `reference_cache`).
pub fn parse(bytes: &[u8]) -> Result<CacheEntry, String> {
    match bytes.get(..8) {
        Some(m) if m == MAGIC => {}
        Some(m) if m == OLD_MAGIC => {
            return Err("is in the old cache format (PNMBREF1, no digest)".into())
        }
        _ => return Err("is not a reference cache file (no PNMBREF2 magic)".into()),
    }
    let u32_at = |at: usize| {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let (Some(width), Some(height), Some(key_len)) = (u32_at(8), u32_at(12), u32_at(16)) else {
        return Err(format!(
            "is cut short in its header ({} bytes)",
            bytes.len()
        ));
    };
    let n = width as u64 * height as u64;
    let expected = HEADER as u64 + key_len as u64 + 4 * n + DIGEST as u64;
    if bytes.len() as u64 != expected {
        return Err(format!("has {} bytes, but its header ({width}x{height} values, a key of {key_len} bytes) says {expected}", bytes.len()));
    }
    let (body, digest) = bytes.split_at(bytes.len() - DIGEST);
    if Sha256::digest(body).as_slice() != digest {
        return Err("does not match its sha256 digest: its bytes were damaged".into());
    }
    let data_at = HEADER + key_len as usize;
    let mut values = Vec::with_capacity(n as usize);
    for (i, c) in body[data_at..].chunks_exact(4).enumerate() {
        let v = f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
        // Written by a bug rather than damaged on disk: the digest matches, the value cannot.
        if !(0.0..=1.0).contains(&v) {
            let (x, y) = (i as u64 % width as u64, i as u64 / width as u64);
            return Err(format!("holds V = {v} at pixel ({x}, {y}), outside [0, 1]"));
        }
        values.push(v);
    }
    Ok(CacheEntry {
        width,
        height,
        key: body[HEADER..data_at].to_vec(),
        values,
    })
}

/// What the cache holds for one key.
#[derive(Debug, PartialEq)]
pub enum Lookup {
    Hit(Vec<f32>),
    /// No file, or one stored for another key or size (stale): trace.
    Miss,
    /// A file that must not be used (damaged, out of range, the old format): the reason, to be
    /// said once with the file's name before it is traced again.
    Damaged(String),
}

/// The cached buffer for `key` at `width`×`height`. `Err` only when the file exists but cannot
/// be read (permissions, I/O): one line naming it and `--no-cache`.
pub fn load_cached(
    dir: &Path,
    key: &str,
    width: u32,
    height: u32,
) -> Result<Lookup, ReferenceError> {
    use std::io::Read;
    let path = cache_path(dir, key);
    let meta = match fs::metadata(&path) {
        Ok(m) => m,
        Err(e) if e.kind() == ErrorKind::NotFound => return Ok(Lookup::Miss),
        Err(source) => return Err(ReferenceError::CacheRead { path, source }),
    };
    // Only a regular file is opened (a link to /dev/zero was read until memory ran out, a FIFO
    // blocked), and no more than the entry this key and size make is read.
    if !meta.is_file() && !meta.is_dir() {
        return Ok(Lookup::Damaged(format!(
            "is {}, not a regular file",
            crate::scene::input_file::kind(&meta.file_type())
        )));
    }
    let expected = (HEADER + key.len() + DIGEST) as u64 + 4 * width as u64 * height as u64;
    let mut bytes = Vec::new();
    let read = fs::File::open(&path).and_then(|f| f.take(expected + 1).read_to_end(&mut bytes));
    if let Err(source) = read {
        return Err(ReferenceError::CacheRead { path, source });
    }
    if bytes.len() as u64 > expected {
        return Ok(Lookup::Damaged(format!(
            "holds more than the {expected} bytes of a {width}x{height} entry"
        )));
    }
    Ok(match parse(&bytes) {
        Ok(e) if e.key == key.as_bytes() && e.width == width && e.height == height => {
            Lookup::Hit(e.values)
        }
        Ok(_) => Lookup::Miss,
        Err(why) => Lookup::Damaged(why),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_is_stable_and_length_prefixed() {
        assert_eq!(cache_key(&[b"ab", b"c"]), cache_key(&[b"ab", b"c"]));
        assert_ne!(cache_key(&[b"ab", b"c"]), cache_key(&[b"a", b"bc"]));
        assert_eq!(cache_key(&[]), "cbf29ce484222325"); // FNV-1a offset basis
        assert_eq!(cache_key(&[b"x"]).len(), 16);
    }

    #[test]
    fn reference_key_depends_on_every_input() {
        let light = RefLight {
            center: glam::Vec3::Y,
            edge_u: glam::Vec3::X,
            edge_v: glam::Vec3::Z,
        };
        let lattice = ReferenceMode::Lattice;
        let base = reference_key(b"scene", &light, &lattice, 1e-3);
        assert_eq!(base, reference_key(b"scene", &light, &lattice, 1e-3));
        assert_ne!(base, reference_key(b"other", &light, &lattice, 1e-3));
        let moved = RefLight {
            center: glam::Vec3::Y * 2.0,
            ..light
        };
        assert_ne!(base, reference_key(b"scene", &moved, &lattice, 1e-3));
        assert_ne!(
            base,
            reference_key(b"scene", &light, &ReferenceMode::DEFAULT_CONTINUOUS, 1e-3)
        );
        assert_ne!(base, reference_key(b"scene", &light, &lattice, 2e-3));
    }

    #[test]
    fn lock_is_exclusive_and_lock_files_left_behind_are_taken() -> Result<(), ReferenceError> {
        let dir = std::env::temp_dir().join(format!("penumbra-ref-lock-{}", std::process::id()));
        let held = lock(&dir, "k", &mut |_| panic!("nothing holds it yet"))?;
        let path = dir.join("k.lock");
        assert!(fs::read_to_string(&path)?.starts_with(&format!("{} ", std::process::id())));
        // A second claim waits until the first is dropped.
        let (tx, rx) = std::sync::mpsc::channel();
        let d = dir.clone();
        let waiter = std::thread::spawn(move || {
            let mut said = String::new();
            let l = lock(&d, "k", &mut |who| said = who.to_string()).unwrap();
            tx.send(said).unwrap();
            drop(l);
        });
        std::thread::sleep(std::time::Duration::from_millis(300));
        assert!(rx.try_recv().is_err(), "the second claim must wait");
        drop(held);
        let said = rx.recv().unwrap();
        assert!(said.starts_with(&std::process::id().to_string()), "{said}");
        waiter.join().unwrap();
        assert!(!path.exists());
        // A lock file left behind is taken over, whoever its pid names now: a dead pid, or a live
        // one (pid 1, this process), as when a signalled run's pid was reused.
        for pid in [u32::MAX - 1, 1, std::process::id()] {
            fs::write(&path, format!("{pid} {}\n", host_name()))?;
            drop(lock(&dir, "k", &mut |_| {
                panic!("a lock file no process holds must not be waited for")
            })?);
        }
        fs::remove_dir_all(&dir)?;
        Ok(())
    }

    #[test]
    fn round_trip_stale_and_cut_short() -> Result<(), ReferenceError> {
        let dir = std::env::temp_dir().join(format!("penumbra-ref-cache-{}", std::process::id()));
        let key = cache_key(&[b"scene", b"lattice"]);
        assert_eq!(load_cached(&dir, &key, 2, 2)?, Lookup::Miss);
        let values = [0.0, 0.25, 1.0, 0.5];
        let path = save_cached(&dir, &key, 2, 2, &values)?;
        assert_eq!(load_cached(&dir, &key, 2, 2)?, Lookup::Hit(values.to_vec()));
        assert_eq!(
            load_cached(&dir, &key, 4, 1)?,
            Lookup::Miss,
            "other size is stale"
        );
        assert!(matches!(
            save_cached(&dir, &key, 3, 3, &values),
            Err(ReferenceError::SizeMismatch {
                expected: 9,
                got: 4
            })
        ));
        fs::write(&path, b"PNMBREF2\x02\x00")?;
        assert_eq!(
            load_cached(&dir, &key, 2, 2)?,
            Lookup::Damaged("is cut short in its header (10 bytes)".into())
        );
        fs::remove_dir_all(&dir)?;
        Ok(())
    }

    /// Damage that keeps the file's size: each is caught by the digest, and values that are no
    /// visibility (a bug's write, digest and all) by the range check.
    #[test]
    fn damage_with_the_size_kept_is_caught() {
        let values: Vec<f32> = (0..64).map(|i| i as f32 / 63.0).collect();
        let key = "0123456789abcdef";
        let good = encode(key, 8, 8, &values);
        assert_eq!(parse(&good).map(|e| e.values), Ok(values.clone()));
        let data_at = HEADER + key.len();
        let damaged = "does not match its sha256 digest: its bytes were damaged";
        let mut flipped = good.clone();
        flipped[data_at + 4 * 9 + 3] ^= 0x40;
        assert_eq!(parse(&flipped), Err(damaged.to_string()));
        let mut zeroed = good.clone();
        zeroed[data_at + 40..data_at + 104].fill(0);
        assert_eq!(parse(&zeroed), Err(damaged.to_string()));
        for (bad, shown) in [
            (7.0f32, "7"),
            (f32::NAN, "NaN"),
            (-0.5, "-0.5"),
            (f32::INFINITY, "inf"),
        ] {
            let mut written = good.clone();
            written[data_at + 4 * 10..data_at + 4 * 11].copy_from_slice(&bad.to_le_bytes());
            assert_eq!(
                parse(&written),
                Err(damaged.to_string()),
                "{bad} written over the payload"
            );
            // The same value with the digest recomputed over it: the range check.
            let mut v = values.clone();
            v[10] = bad;
            assert_eq!(
                parse(&encode(key, 8, 8, &v)),
                Err(format!("holds V = {shown} at pixel (2, 1), outside [0, 1]"))
            );
        }
        // Format 1 (no digest) is never trusted.
        let mut old = good[..good.len() - DIGEST].to_vec();
        old[..8].copy_from_slice(OLD_MAGIC);
        assert_eq!(
            parse(&old),
            Err("is in the old cache format (PNMBREF1, no digest)".to_string())
        );
        // A header claiming more than the file holds allocates nothing.
        let mut huge = good.clone();
        huge[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(parse(&huge)
            .unwrap_err()
            .starts_with(&format!("has {} bytes, but its header", good.len())));
    }
}
