//! Every parser of user input, on bytes in memory, as the fuzz targets (fuzz/) and the bounded
//! stable runs (tests/fuzz_parsers.rs) drive them. Each returns the parser's own Result: an `Err`
//! is a rejected input (fine); a panic, hang or runaway allocation is a bug.

use crate::assets::LoadedMesh;
use crate::scene::{MeshDirs, Scene};
use crate::Result;
use std::path::Path;

/// A folder that does not exist: mesh files named by fuzzed scenes resolve to nothing.
const NOWHERE: &str = "/nonexistent/penumbra-inputs";

/// A scene file (mesh files and `cache:` paths resolve in a folder that does not exist).
pub fn scene_toml(text: &str) -> Result<Scene> {
    let dirs = MeshDirs {
        scene_dir: Some(Path::new(NOWHERE)),
        cache: Some(Path::new(NOWHERE)),
        max_mesh_bytes: None,
    };
    Ok(Scene::parse_in(text, "input.toml", dirs, &[])?)
}

/// A scene file with `--set` overrides.
pub fn scene_toml_with(text: &str, overrides: &[(String, String)]) -> Result<Scene> {
    let dirs = MeshDirs {
        scene_dir: Some(Path::new(NOWHERE)),
        cache: Some(Path::new(NOWHERE)),
        max_mesh_bytes: None,
    };
    Ok(Scene::parse_in(text, "input.toml", dirs, overrides)?)
}

/// A Wavefront OBJ mesh.
pub fn obj(text: &str) -> Result<usize> {
    Ok(crate::scene::parse_obj(text, "input.obj")?)
}

fn in_file<T>(r: std::result::Result<T, crate::assets::Failure>, name: &str) -> Result<T> {
    r.map_err(|f| f.in_file(Path::new(name)).into())
}

/// A PLY mesh (ASCII or binary).
pub fn ply(bytes: &[u8]) -> Result<LoadedMesh> {
    in_file(crate::assets::parse_ply(bytes), "input.ply")
}

/// An OFF mesh.
pub fn off(text: &str) -> Result<LoadedMesh> {
    in_file(crate::assets::parse_off(text), "input.off")
}

/// A JS-array mesh module (`positions = [...]`, `cells = [...]`).
pub fn js_arrays(text: &str) -> Result<LoadedMesh> {
    in_file(crate::assets::parse_js_arrays(text), "input.js")
}

/// A sweep spec, under the command line's default configuration limit (as `sweep` parses it).
pub fn sweep_spec(text: &str) -> Result<Vec<String>> {
    use crate::studies::compare::{plan, sweep};
    sweep::parse_spec_within(text, "input.toml", plan::DEFAULT_MAX_CONFIGS)
}

/// A results.jsonl file.
pub fn results_jsonl(text: &str) -> Result<usize> {
    crate::report::results::parse_results(text, Path::new("input.jsonl")).map(|rows| rows.len())
}

/// A reference cache file (`<key>.vis`, src/reference/cache.rs) as it is read: the number of
/// values, or what is wrong with it.
pub fn reference_cache(bytes: &[u8]) -> Result<usize> {
    crate::reference::parse_cache_file(bytes)
        .map(|e| e.values.len())
        .map_err(|message| crate::Error::io_text("input.vis".into(), message))
}

/// The same with its last 32 bytes replaced by the digest of the rest, so that mutated inputs
/// reach the checks behind the digest (the size and the values) instead of stopping at it.
pub fn reference_cache_resealed(bytes: &[u8]) -> Result<usize> {
    use sha2::{Digest, Sha256};
    let mut sealed = bytes.to_vec();
    if let Some(body) = bytes.len().checked_sub(32) {
        let digest = Sha256::digest(&bytes[..body]);
        sealed[body..].copy_from_slice(&digest);
    }
    reference_cache(&sealed)
}
