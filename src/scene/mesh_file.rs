//! Mesh files a scene names: where `file` points (the scene's folder, the embedded meshes of
//! built-in scenes, or the asset cache with `cache:`) and which loader reads it.

use super::mesh_input::{self, Refusal};
use super::obj;
use super::raw_mesh::RawMesh;
use crate::{Error, Result};
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The asset layer a program registers (the lab's `assets`): where the asset cache is, which
/// fetch groups exist, the pinned digests of cached files, and the loaders of the registry mesh
/// formats (.off, .ply, .ply.gz, .js). Without one, scenes read OBJ files and built-in meshes,
/// and `cache:` paths or registry formats are errors that say so.
pub struct AssetLayer {
    /// The asset cache when none is given; Err: the message why there is none.
    pub default_cache_dir: fn() -> std::result::Result<PathBuf, String>,
    /// Whether a cache path's first component names a fetch group.
    pub is_group: fn(&str) -> bool,
    /// Ok when a cached file still has its pinned content; else one sentence why not.
    pub check_pinned: fn(&str, &Path) -> std::result::Result<(), String>,
    /// Loads a registry-format mesh reading at most `max` bytes: (positions, triangle indices);
    /// Err: the message, leading with the path.
    pub load_mesh: fn(&Path, u64) -> std::result::Result<MeshArrays, String>,
}

/// A loaded mesh: positions and triangle indices.
pub(crate) type MeshArrays = (Vec<[f32; 3]>, Vec<u32>);

static ASSET_LAYER: OnceLock<AssetLayer> = OnceLock::new();

/// Registers the asset layer; only the first call counts.
pub fn register_asset_layer(layer: AssetLayer) {
    let _ = ASSET_LAYER.set(layer);
}

fn asset_layer(what: &str) -> Result<&'static AssetLayer> {
    ASSET_LAYER.get().ok_or_else(|| Error::Asset(format!("{what}: needs the asset layer (the penumbra binary registers it; penumbra_lab::install)")))
}

/// The asset cache folder: the registered layer's default (`$PENUMBRA_CACHE`, else `~/.cache/penumbra`).
pub(crate) fn default_cache_dir() -> Result<PathBuf> {
    (asset_layer("the asset cache")?.default_cache_dir)().map_err(Error::Asset)
}

/// The fetch group a cache path names (`meshes/cow.off`: `meshes`), else `all`.
pub(crate) fn fetch_group(rel: &str) -> &str {
    rel.split('/')
        .next()
        .filter(|g| ASSET_LAYER.get().is_some_and(|l| (l.is_group)(g)))
        .unwrap_or("all")
}

/// `file = "cache:meshes/cow.off"` reads `<cache>/meshes/cow.off`.
pub const CACHE_PREFIX: &str = "cache:";

pub(crate) const FORMATS: &str = ".obj, .off, .ply, .ply.gz or .js";

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
/// whose pinned digest no longer matches (the asset layer's check_pinned) one that says how to replace it.
pub fn cache_path(file: &str, cache: Option<&Path>) -> Result<PathBuf> {
    let rel = file.strip_prefix(CACHE_PREFIX).unwrap_or(file);
    if rel.is_empty() || Path::new(rel).is_absolute() || rel.split(['/', '\\']).any(|c| c == "..") {
        return Err(Error::mesh(
            file,
            "a cache path must be relative and stay inside the cache, e.g. `cache:meshes/cow.off`",
        ));
    }
    let root = match cache {
        Some(dir) => dir.to_path_buf(),
        None => default_cache_dir()?,
    };
    let path = root.join(rel);
    if !path.exists() {
        // The first path component is the fetch group (meshes/, trees/, panoramas/).
        let group = fetch_group(rel);
        return Err(Error::MissingAsset {
            file: file.to_string(),
            missing: path.display().to_string(),
            group: group.to_string(),
        });
    }
    (asset_layer(file)?.check_pinned)(rel, &path).map_err(|why| Error::mesh(file, why))?;
    Ok(path)
}

/// Loads a mesh named by a scene; errors name the mesh file and the line or element. `origin`
/// (the scene file) and `which` (`mesh 2`) name the key in errors about the file itself.
/// Every error is one line naming the scene file, the mesh and its `file` once:
/// `s.toml: mesh 2: file = "m.off": line 2: file ends early: …`.
pub(crate) fn load(file: &str, origin: &str, which: &str, dirs: MeshDirs) -> Result<RawMesh> {
    // The loaders lead with what they read (`lead`: the path, or `file` itself); `file = …` names it.
    let named = |lead: &str, e: Error| {
        // A missing asset keeps its kind: each front end says how to fetch it.
        if let Error::MissingAsset { missing, group, .. } = e {
            return Error::MissingAsset {
                file: format!("{origin}: {which}: file = {file:?}"),
                missing,
                group,
            };
        }
        let text = e.to_string();
        let why = text
            .strip_prefix(lead)
            .and_then(|t| t.strip_prefix(": "))
            .unwrap_or(&text);
        let message = format!("{which}: file = {file:?}: {why}");
        // Over the cap keeps its kind too: each front end says how to raise it.
        match e {
            Error::MeshCap { cap_mib, .. } => Error::MeshCap {
                message: format!("{origin}: {message}"),
                cap_mib,
            },
            _ => Error::scene(origin, message),
        }
    };
    let path = if file.starts_with(CACHE_PREFIX) {
        cache_path(file, dirs.cache).map_err(|e| named(file, e))?
    } else if origin.starts_with("builtin:") {
        return obj::load_embedded(file).map_err(|e| named(file, e));
    } else {
        dirs.scene_dir
            .map(|d| d.join(file))
            .unwrap_or_else(|| file.into())
    };
    let max = dirs
        .max_mesh_bytes
        .unwrap_or_else(mesh_input::max_mesh_bytes);
    // Metadata first: a FIFO would block the open, a device or a huge file would fill memory.
    if path.exists() {
        mesh_input::check_mesh_file(&path, max).map_err(|refusal| {
            let lead = format!("{which}: file = {file:?}");
            match refusal {
                Refusal::Unreadable(why) => Error::scene(origin, format!("{lead}: {why}")),
                Refusal::OverCap { why, cap_mib } => Error::MeshCap {
                    message: format!("{origin}: {lead}: {why}"),
                    cap_mib,
                },
            }
        })?;
    }
    load_path(&path, max).map_err(|e| named(&path.display().to_string(), e))
}

fn load_path(path: &Path, max: u64) -> Result<RawMesh> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let inner = name.strip_suffix(".gz").unwrap_or(&name);
    match Path::new(inner).extension().and_then(|e| e.to_str()) {
        Some("obj") if inner == name => obj::load_file(path, max),
        Some("off" | "ply" | "js") => {
            let (positions, indices) =
                (asset_layer(&path.display().to_string())?.load_mesh)(path, max)
                    .map_err(Error::Asset)?;
            let positions = positions.iter().map(|p| Vec3::from(*p)).collect();
            Ok(RawMesh {
                positions,
                normals: None,
                indices,
            })
        }
        _ => Err(Error::mesh(
            path.display().to_string(),
            format!("unknown mesh format (expected {FORMATS})"),
        )),
    }
}
