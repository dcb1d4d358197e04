//! Mesh files a scene names: where `file` points (the scene's folder, the embedded meshes of
//! built-in scenes, or the asset cache with `cache:`) and which loader reads it.

use super::raw_mesh::RawMesh;
use super::obj;
use crate::scene::assets;
use crate::{Error, Result};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// `file = "cache:meshes/cow.off"` reads `<cache>/meshes/cow.off`.
pub const CACHE_PREFIX: &str = "cache:";

pub const FORMATS: &str = ".obj, .off, .ply, .ply.gz or .js";

/// Where relative and `cache:` mesh paths resolve.
#[derive(Clone, Copy, Debug, Default)]
pub struct MeshDirs<'a> {
    /// The scene file's folder; `None` for built-in scenes (their meshes are embedded).
    pub scene_dir: Option<&'a Path>,
    /// The asset cache; `None`: `$PENUMBRA_CACHE`, else `~/.cache/penumbra` (looked up only when used).
    pub cache: Option<&'a Path>,
    /// The cap on a mesh file's size in bytes (decompressed, for gzip); `None`: the run's cap
    /// (`--max-mesh-mib`, else 2 GiB).
    pub max_mesh_bytes: Option<u64>,
}

/// Resolves a `cache:` path; a missing file is an error that says how to fetch it, and a file
/// whose pinned digest no longer matches (assets::check_pinned) one that says how to replace it.
pub fn cache_path(file: &str, cache: Option<&Path>) -> Result<PathBuf> {
    let rel = file.strip_prefix(CACHE_PREFIX).unwrap_or(file);
    if rel.is_empty() || Path::new(rel).is_absolute() || rel.split(['/', '\\']).any(|c| c == "..") {
        return Err(Error::mesh(file, "a cache path must be relative and stay inside the cache, e.g. `cache:meshes/cow.off`"));
    }
    let root = match cache {
        Some(dir) => dir.to_path_buf(),
        None => assets::default_cache_dir()?,
    };
    let path = root.join(rel);
    if !path.exists() {
        // The first path component is the fetch group (meshes/, trees/, panoramas/).
        let group = rel.split('/').next().filter(|g| g.parse::<assets::Group>().is_ok()).unwrap_or("all");
        return Err(Error::mesh(
            file,
            format!(
                "not in the asset cache ({} is missing): run `penumbra assets fetch --group {group}` (cache folder: --cache or $PENUMBRA_CACHE)",
                path.display()
            ),
        ));
    }
    assets::check_pinned(rel, &path).map_err(|why| Error::mesh(file, why))?;
    Ok(path)
}

/// Loads a mesh named by a scene; errors name the mesh file and the line or element. `origin`
/// (the scene file) and `which` (`mesh 2`) name the key in errors about the file itself.
/// Every error is one line naming the scene file, the mesh and its `file` once:
/// `s.toml: mesh 2: file = "m.off": line 2: file ends early: …`.
pub fn load(file: &str, origin: &str, which: &str, dirs: MeshDirs) -> Result<RawMesh> {
    // The loaders lead with what they read (`lead`: the path, or `file` itself); `file = …` names it.
    let named = |lead: &str, e: Error| {
        let text = e.to_string();
        let why = text.strip_prefix(lead).and_then(|t| t.strip_prefix(": ")).unwrap_or(&text);
        Error::scene(origin, format!("{which}: file = {file:?}: {why}"))
    };
    let path = if file.starts_with(CACHE_PREFIX) {
        cache_path(file, dirs.cache).map_err(|e| named(file, e))?
    } else if origin.starts_with("builtin:") {
        return obj::load_embedded(file).map_err(|e| named(file, e));
    } else {
        dirs.scene_dir.map(|d| d.join(file)).unwrap_or_else(|| file.into())
    };
    let max = dirs.max_mesh_bytes.unwrap_or_else(assets::max_mesh_bytes);
    // Metadata first: a FIFO would block the open, a device or a huge file would fill memory.
    if path.exists() {
        assets::check_mesh_file(&path, max).map_err(|why| Error::scene(origin, format!("{which}: file = {file:?}: {why}")))?;
    }
    load_path(&path, max).map_err(|e| named(&path.display().to_string(), e))
}

fn load_path(path: &Path, max: u64) -> Result<RawMesh> {
    let name = path.file_name().map(|n| n.to_string_lossy().to_lowercase()).unwrap_or_default();
    let inner = name.strip_suffix(".gz").unwrap_or(&name);
    match Path::new(inner).extension().and_then(|e| e.to_str()) {
        Some("obj") if inner == name => obj::load_file(path, max),
        Some("off" | "ply" | "js") => {
            let mesh = assets::load_mesh_capped(path, max)?;
            let positions = mesh.positions.iter().map(|p| Vec3::from(*p)).collect();
            Ok(RawMesh { positions, normals: None, indices: mesh.indices })
        }
        _ => Err(Error::mesh(path.display().to_string(), format!("unknown mesh format (expected {FORMATS})"))),
    }
}
