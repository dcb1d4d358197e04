//! Where a row came from: the scene file's hash, the mesh files' digests, the `--set` overrides,
//! and, for sweeps, the spec and the shard. With the row's `version` (crate and git hash) and
//! `adapter`, this is what `merge` checks before joining shards and what a report lists.

use crate::scene::{self, Scene};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// `compare`, `sweep` or `bench seed-table2`.
    pub command: String,
    /// The scene file as given (`builtin:default` for a built-in scene).
    pub scene_file: String,
    /// sha256 of the scene file's text.
    pub scene_sha256: String,
    /// Every mesh file the scene names, with its sha256.
    #[serde(default)]
    pub meshes: Vec<MeshDigest>,
    /// sha256 of the loaded triangles (positions and indices): subdivision and instancing included.
    #[serde(default)]
    pub geometry_sha256: String,
    /// `--set` render overrides, as given.
    #[serde(default)]
    pub overrides: Vec<String>,
    /// The sweep spec and shard this row was run in; `None` outside sweeps.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spec: Option<SpecRef>,
}

#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct MeshDigest {
    pub file: String,
    pub sha256: String,
}

#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SpecRef {
    pub file: String,
    /// sha256 of the spec's text: shards of one sweep share it.
    pub sha256: String,
    /// Configurations in the whole spec, and this row's position among them (from 0).
    pub configs: usize,
    pub config: usize,
    /// `[index, count]`: shard `index` of `count` (`[0, 1]` for an unsharded sweep).
    pub shard: [u32; 2],
}

/// Lowercase hex sha256.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The text of a scene as `Scene::load` read it: a built-in's embedded text, else the file.
fn scene_source(scene: &Scene) -> Option<(String, Option<PathBuf>)> {
    match scene.origin.strip_prefix("builtin:") {
        Some(name) => scene::builtin_source(name).map(|t| (t.to_string(), None)),
        None => {
            let path = PathBuf::from(&scene.origin);
            let text = std::fs::read_to_string(&path).ok()?;
            Some((text, path.parent().map(Path::to_path_buf)))
        }
    }
}

/// The mesh files the scene text names (`[[mesh]] file = …`), digested where they are found.
fn mesh_digests(
    text: &str,
    dir: Option<&Path>,
    builtin: bool,
    cache: Option<&Path>,
) -> Vec<MeshDigest> {
    let Ok(table) = toml::from_str::<toml::Table>(text) else {
        return Vec::new();
    };
    let files = table
        .get("mesh")
        .and_then(|m| m.as_array())
        .into_iter()
        .flatten()
        .filter_map(|m| m.get("file")?.as_str());
    files
        .map(|file| {
            let bytes = if file.starts_with(scene::CACHE_PREFIX) {
                scene::cache_path(file, cache)
                    .ok()
                    .and_then(|p| std::fs::read(p).ok())
            } else if builtin {
                scene::embedded_source(file).map(|t| t.as_bytes().to_vec())
            } else {
                std::fs::read(dir.map(|d| d.join(file)).unwrap_or_else(|| file.into())).ok()
            };
            // A file that cannot be read now was read when the scene loaded; say so, never guess.
            let sha256 = bytes
                .map(|b| sha256_hex(&b))
                .unwrap_or_else(|| "unreadable".into());
            MeshDigest {
                file: file.to_string(),
                sha256,
            }
        })
        .collect()
}

fn geometry_digest(scene: &Scene) -> String {
    let mut h = Sha256::new();
    for v in &scene.vertices {
        for c in v.position {
            h.update(c.to_le_bytes());
        }
    }
    for i in &scene.indices {
        h.update(i.to_le_bytes());
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

impl Provenance {
    /// The provenance of runs on `scene` (loaded with `overrides`); `cache`: the asset cache its
    /// `cache:` meshes came from (`None`: the default).
    pub fn of_scene(
        command: &str,
        scene: &Scene,
        overrides: &[String],
        cache: Option<&Path>,
    ) -> Provenance {
        let (scene_sha256, meshes) = match scene_source(scene) {
            Some((text, dir)) => (
                sha256_hex(text.as_bytes()),
                mesh_digests(&text, dir.as_deref(), dir.is_none(), cache),
            ),
            None => ("unreadable".into(), Vec::new()),
        };
        Provenance {
            command: command.to_string(),
            scene_file: scene.origin.clone(),
            scene_sha256,
            meshes,
            geometry_sha256: geometry_digest(scene),
            overrides: overrides.to_vec(),
            spec: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digests_of_the_default_scene() {
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        let scene = Scene::load("default", &[("resolution".into(), "32".into())]).unwrap();
        let p = Provenance::of_scene("compare", &scene, &["resolution=32".into()], None);
        assert_eq!(p.scene_file, "builtin:default");
        assert_eq!(
            p.scene_sha256,
            sha256_hex(scene::builtin_source("default").unwrap().as_bytes())
        );
        assert_eq!(p.meshes.len(), 1);
        assert_eq!(p.meshes[0].file, "bunny-small.obj");
        assert_eq!(
            p.meshes[0].sha256,
            sha256_hex(
                scene::embedded_source("bunny-small.obj")
                    .unwrap()
                    .as_bytes()
            )
        );
        assert_eq!(p.geometry_sha256.len(), 64);
        let other = Scene::load("analytic-square", &[]).unwrap();
        assert_ne!(
            Provenance::of_scene("compare", &other, &[], None).geometry_sha256,
            p.geometry_sha256
        );
    }
}
