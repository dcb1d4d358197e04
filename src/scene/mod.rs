//! Scenes: a small TOML format (docs/scene-format.md), built-in named scenes, meshes.

mod bounds;
mod builtin;
mod catalog;
mod coords;
mod cube_window;
pub(crate) mod emitter;
mod emitter_def;
pub(crate) mod environment;
mod format;
mod given;
pub(crate) mod input_file;
mod instances;
pub(crate) mod light;
pub(crate) mod light_checks;
mod loop_subdivision;
mod mesh;
mod mesh_def;
pub(crate) mod mesh_file;
pub(crate) mod mesh_input;
mod model;
mod obj;
mod overrides;
mod raw_mesh;
pub(crate) mod rays;
mod settings;
mod subdivide;

pub use builtin::{builtin_names, builtin_source};
pub use catalog::{area_light_names, catalog};
pub use coords::MAX_COORDINATE;
pub use emitter::{DiskLight, Emitter, LightKind, PointLight, SpotLight};
pub use emitter_def::MAX_SUN_DIAMETER_DEG;
pub use given::{settings_from_pairs, GivenMesh};
pub use mesh::Vertex;
pub use mesh_file::{cache_path, register_asset_layer, AssetLayer, MeshDirs, CACHE_PREFIX};
pub use model::{Camera, Scene};
pub use obj::embedded_source;
pub use overrides::is_render_key;
pub use settings::{BiasDef, CullMode, HybridDef, MapKind};
pub(crate) use settings::{RasterChoice, RenderSettings, SelfShadow};

use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// Parses OBJ text (as a scene's `file = "x.obj"` would); returns its triangle count.
pub fn parse_obj(text: &str, label: &str) -> Result<usize> {
    obj::parse(text, label).map(|m| m.indices.len() / 3)
}

impl Scene {
    /// Loads a scene by built-in name or file path, applying `key=value` overrides to its render settings.
    pub fn load(name_or_path: &str, overrides: &[(String, String)]) -> Result<Scene> {
        Self::load_in(name_or_path, overrides, None)
    }

    /// As `load`, with `cache:` mesh paths resolved in `cache` (`None`: the default asset cache).
    pub fn load_in(
        name_or_path: &str,
        overrides: &[(String, String)],
        cache: Option<&Path>,
    ) -> Result<Scene> {
        if name_or_path.trim().is_empty() {
            return Err(Error::Input {
                input: crate::Input::Scene,
                value: name_or_path.to_string(),
                why: format!(
                    "empty; give a built-in scene ({}) or a path to a scene TOML file",
                    builtin_names().join(", ")
                ),
            });
        }
        if let Some(text) = builtin_source(name_or_path) {
            let origin = format!("builtin:{name_or_path}");
            return Self::parse_in(
                text,
                &origin,
                MeshDirs {
                    scene_dir: None,
                    cache,
                    max_mesh_bytes: None,
                },
                overrides,
            );
        }
        let path = PathBuf::from(name_or_path);
        if !path.exists() {
            return Err(Error::scene(
                name_or_path,
                format!(
                    "no such scene file or built-in scene (built-ins: {})",
                    builtin_names().join(", ")
                ),
            ));
        }
        let text = input_file::read_text(
            &path,
            input_file::TEXT_CAP,
            "the 256 MiB cap on scene files",
        )
        .map_err(|e| Error::scene(name_or_path, format!("cannot read: {e}")))?;
        Self::parse_in(
            &text,
            name_or_path,
            MeshDirs {
                scene_dir: path.parent(),
                cache,
                max_mesh_bytes: None,
            },
            overrides,
        )
    }

    /// Parses scene text; mesh files resolve against `dir` (or the embedded meshes for built-ins),
    /// `cache:` paths against the default asset cache.
    pub fn parse(
        text: &str,
        origin: &str,
        dir: Option<&Path>,
        overrides: &[(String, String)],
    ) -> Result<Scene> {
        Self::parse_in(
            text,
            origin,
            MeshDirs {
                scene_dir: dir,
                cache: None,
                max_mesh_bytes: None,
            },
            overrides,
        )
    }

    /// As `parse`, with the folders mesh files resolve against given explicitly (tests, `--cache`).
    pub fn parse_in(
        text: &str,
        origin: &str,
        dirs: MeshDirs,
        overrides: &[(String, String)],
    ) -> Result<Scene> {
        let def = format::parse(text, origin, overrides)?;
        format::build(def, origin, dirs)
    }
}
