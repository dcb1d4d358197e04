//! `penumbra scenes`: every built-in scene with its triangle count, where its meshes come from and
//! whether the cached ones are present.

use super::builtin;
use super::format;
use super::mesh_def::MeshDef;
use super::mesh_file;
use super::mesh_file::CACHE_PREFIX;
use super::model::Scene;
use std::path::{Path, PathBuf};

pub struct CatalogEntry {
    pub name: &'static str,
    pub description: String,
    /// Stated in the file (`triangles = …`), else counted by loading; None when that is not possible.
    pub triangles: Option<u64>,
    /// Each mesh's source: `plane` (built-in shape), `embedded bunny-small.obj`, `cache:meshes/cow.off`.
    pub sources: Vec<String>,
    /// Cache files the scene needs that are absent.
    pub missing: Vec<PathBuf>,
    /// The asset groups that hold what is missing (each front end says how to fetch them).
    pub fetch_groups: Vec<String>,
}

fn source(m: &MeshDef) -> String {
    match (&m.builtin, &m.file) {
        (Some(b), _) => b.clone(),
        (None, Some(f)) if f.starts_with(CACHE_PREFIX) => f.clone(),
        (None, Some(f)) => format!("embedded {f}"),
        (None, None) => "?".into(),
    }
}

/// The built-in scenes; `cache` is the asset cache to look in (None: the default one).
pub fn catalog(cache: Option<&Path>) -> Vec<CatalogEntry> {
    let cache_dir = cache
        .map(Path::to_path_buf)
        .or_else(|| mesh_file::default_cache_dir().ok());
    builtin::BUILTIN_SCENES
        .iter()
        .map(|&(name, text)| {
            let origin = format!("builtin:{name}");
            let (mut description, mut triangles) = (String::new(), None);
            let (mut sources, mut missing, mut groups) =
                (Vec::new(), Vec::new(), Vec::<String>::new());
            if let Ok(def) = format::parse(text, &origin, &[]) {
                description = def.description.clone().unwrap_or_default();
                triangles = def.triangles;
                // The panorama of an [environment] is a cached asset like a mesh.
                let files = def
                    .meshes
                    .iter()
                    .map(|m| (source(m), m.file.clone()))
                    .chain(
                        def.environment
                            .iter()
                            .map(|e| (e.panorama.clone(), Some(e.panorama.clone()))),
                    );
                for (src, file) in files {
                    sources.push(src);
                    if let Some(rel) = file.as_deref().and_then(|f| f.strip_prefix(CACHE_PREFIX)) {
                        let present = cache_dir.as_ref().is_some_and(|d| d.join(rel).is_file());
                        if !present {
                            missing.push(
                                cache_dir
                                    .as_ref()
                                    .map(|d| d.join(rel))
                                    .unwrap_or_else(|| rel.into()),
                            );
                            let group = mesh_file::fetch_group(rel).to_string();
                            if !groups.contains(&group) {
                                groups.push(group);
                            }
                        }
                    }
                }
            }
            if triangles.is_none() && missing.is_empty() {
                triangles = Scene::load_in(name, &[], cache)
                    .ok()
                    .map(|s| s.triangle_count() as u64);
            }
            sources.dedup();
            CatalogEntry {
                name,
                description,
                triangles,
                sources,
                missing,
                fetch_groups: groups,
            }
        })
        .collect()
}

/// The built-in scenes lit by an area light (not a panorama), read from their files alone, so
/// no mesh or panorama has to be present.
pub fn area_light_names() -> Vec<&'static str> {
    builtin::BUILTIN_SCENES
        .iter()
        .filter(|(name, text)| {
            format::parse(text, &format!("builtin:{name}"), &[])
                .is_ok_and(|d| d.environment.is_none())
        })
        .map(|(n, _)| *n)
        .collect()
}
