//! The scene file's `[environment]` section (docs/scene-format.md, docs/environment.md):
//!
//! ```toml
//! [environment]
//! panorama = "cache:panoramas/sunrise.exr"   # or a file beside the scene: equirectangular EXR/HDR
//! rotation_deg = 90.0                         # about +y, default 0
//! intensity = 1.0                             # radiance scale, default 1
//! ```

use super::panorama::Panorama;
use super::Environment;
use crate::scene::light::AreaLight;
use crate::scene::mesh_file::{cache_path, MeshDirs, CACHE_PREFIX};
use crate::{Error, Result};
use glam::Vec3;
use serde::Deserialize;

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub(crate) struct EnvironmentDef {
    pub(crate) panorama: String,
    #[serde(default)]
    pub(crate) rotation_deg: f32,
    #[serde(default = "one")]
    pub(crate) intensity: f32,
}

fn one() -> f32 {
    1.0
}

pub(crate) fn build(def: &EnvironmentDef, origin: &str, dirs: MeshDirs) -> Result<Environment> {
    if !def.rotation_deg.is_finite() {
        return Err(Error::scene(
            origin,
            format!(
                "environment.rotation_deg = {}: must be a finite number",
                def.rotation_deg
            ),
        ));
    }
    if !(def.intensity.is_finite() && def.intensity > 0.0) {
        return Err(Error::scene(
            origin,
            format!(
                "environment.intensity = {}: must be a positive finite number",
                def.intensity
            ),
        ));
    }
    let what = format!("environment.panorama = `{}`", def.panorama);
    let path = if def.panorama.starts_with(CACHE_PREFIX) {
        cache_path(&def.panorama, dirs.cache).map_err(|e| match e {
            // A missing asset keeps its kind: each front end says how to fetch it.
            Error::MissingAsset { missing, group, .. } => Error::MissingAsset {
                file: format!("{origin}: {what}: {}", def.panorama),
                missing,
                group,
            },
            e => Error::scene(origin, format!("{what}: {e}")),
        })?
    } else {
        match dirs.scene_dir {
            Some(dir) => dir.join(&def.panorama),
            None => return Err(Error::scene(origin, format!("{what}: a built-in scene reads panoramas from the cache only (`cache:panoramas/NAME.exr`)"))),
        }
    };
    if !path.is_file() {
        return Err(Error::scene(
            origin,
            format!("{what}: no such file {}", path.display()),
        ));
    }
    let panorama = Panorama::load(&path, &what).map_err(|e| Error::scene(origin, e.to_string()))?;
    if panorama.power() <= 0.0 {
        return Err(Error::scene(
            origin,
            format!("{what}: the panorama is black: nothing would be lit"),
        ));
    }
    Ok(Environment::new(
        def.panorama.clone(),
        panorama,
        def.rotation_deg,
        def.intensity,
    ))
}

/// A square light one diagonal above the meshes, facing down: what the area-light methods (and
/// shadow-map frusta) read in an environment-lit scene. Environment methods ignore it.
pub(crate) fn light_above(min: Vec3, max: Vec3) -> AreaLight {
    let diag = (max - min).length().max(1e-3);
    let mid = (min + max) * 0.5;
    AreaLight {
        center: Vec3::new(mid.x, max.y + diag, mid.z),
        edge_u: Vec3::X * 0.1 * diag,
        edge_v: Vec3::Z * 0.1 * diag,
    }
}
