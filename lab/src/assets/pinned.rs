//! The asset cache is checked on read, as the reference cache is: a file that `fetch` placed
//! under a pinned digest (manifest.rs) is used only while it still has that digest. A file that
//! was damaged or replaced after the fetch would otherwise change every figure of its scenes
//! silently. Files the manifest does not name (a user's own) have no digest to check.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::digest::sha256_file;
use super::manifest::FILES;

/// Ok when `rel` (a path inside the cache, `meshes/cow.off`) is not pinned, or `path` holds its
/// pinned content; else one sentence naming the file, what differs and the fetch that replaces
/// it. Each file is hashed once per process.
pub(crate) fn check_pinned(rel: &str, path: &Path) -> Result<(), String> {
    static VERIFIED: Mutex<BTreeSet<PathBuf>> = Mutex::new(BTreeSet::new());
    // `meshes/./cow.off` and `meshes//cow.off` name the same file as `meshes/cow.off`.
    let parts: Vec<&str> = rel
        .split(['/', '\\'])
        .filter(|c| !c.is_empty() && *c != ".")
        .collect();
    let Some(file) = FILES
        .iter()
        .find(|f| f.dest.split('/').eq(parts.iter().copied()))
    else {
        return Ok(());
    };
    if VERIFIED.lock().is_ok_and(|v| v.contains(path)) {
        return Ok(());
    }
    let fetch = format!(
        "run `penumbra assets fetch --group {}` to fetch it again",
        file.group
    );
    let (got, size) =
        sha256_file(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    if size != file.size || got != file.sha256 {
        return Err(format!(
            "{} is not the file the asset cache pinned ({size} bytes with sha256 {got}; pinned: {} bytes with sha256 {}): it was damaged or replaced; {fetch}",
            path.display(),
            file.size,
            file.sha256
        ));
    }
    if let Ok(mut v) = VERIFIED.lock() {
        v.insert(path.to_path_buf());
    }
    Ok(())
}
