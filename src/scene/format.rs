//! The scene file: TOML, unknown keys rejected, every number checked finite.

use super::coords::finite;
use super::emitter_def::LightDef;
use super::mesh::{self, Vertex};
use super::mesh_def::MeshDef;
use super::mesh_file::MeshDirs;
use super::model::{Camera, Scene};
use super::settings::{CullMode, MapKind, RenderSettings};
use crate::scene::emitter::Emitter;
use crate::scene::light::{AreaLight, Bounds};
use crate::{Error, Result};
use glam::Vec3;
use serde::Deserialize;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneDef {
    pub(crate) name: Option<String>,
    pub(crate) description: Option<String>,
    /// Triangle count the author states; checked against what loads.
    pub(crate) triangles: Option<u64>,
    pub(crate) camera: CameraDef,
    /// Optional when `[environment]` lights the scene.
    pub(crate) light: Option<LightDef>,
    pub(crate) environment: Option<crate::scene::environment::scene::EnvironmentDef>,
    #[serde(default)]
    pub(crate) render: RenderSettings,
    #[serde(default, rename = "mesh")]
    pub(crate) meshes: Vec<MeshDef>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(crate) struct CameraDef {
    pub(crate) eye: [f32; 3],
    pub(crate) target: [f32; 3],
    #[serde(default = "default_up")]
    pub(crate) up: [f32; 3],
    pub(crate) fov_y_deg: f32,
}

fn default_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}

/// TOML text → definition, with `key=value` overrides of its render settings applied. Errors in
/// the file give the line, column, key and value; an override's is an [`Error::Setting`] naming it.
pub(crate) fn parse(text: &str, origin: &str, overrides: &[(String, String)]) -> Result<SceneDef> {
    let mut table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        Error::scene(origin, toml_message(text, &e, "TOML syntax error"))
    })?;
    // The file alone first, from its text, so type errors carry a position.
    let def: SceneDef = toml::from_str(text)
        .map_err(|e: toml::de::Error| Error::scene(origin, toml_message(text, &e, "")))?;
    if overrides.is_empty() {
        return Ok(def);
    }
    super::overrides::apply_overrides(&mut table, overrides, origin)?;
    SceneDef::deserialize(toml::Value::Table(table)).map_err(|e: toml::de::Error| {
        // The file deserialized alone, so an override is at fault: find which.
        let culprit = overrides.iter().find(|o| {
            let mut t: toml::Table = text.parse().unwrap_or_default();
            super::overrides::apply_overrides(&mut t, std::slice::from_ref(o), origin).is_ok()
                && SceneDef::deserialize(toml::Value::Table(t)).is_err()
        });
        let why = plain_message(&e);
        match culprit {
            Some((k, v)) => Error::Setting {
                origin: None,
                key: k.clone(),
                value: Some(v.clone()),
                why,
            },
            None => Error::Param(format!("render settings: {why}")),
        }
    })
}

/// serde's wording for the one untagged enum, in the format's terms.
fn plain_message(e: &toml::de::Error) -> String {
    let msg = e.message().replace('\n', " ").trim().to_string();
    if msg.contains("untagged enum Scale") {
        return "expected a number or an array [x, y, z]".into();
    }
    msg
}

/// `line L, column C: [table] key = value: message`, from the error's span in `text`.
fn toml_message(text: &str, e: &toml::de::Error, lead: &str) -> String {
    let msg = plain_message(e);
    let lead = if lead.is_empty() {
        String::new()
    } else {
        format!("{lead} ")
    };
    match e.span() {
        Some(span) => {
            let start = span.start.min(text.len());
            let before = &text[..start];
            let line = before.matches('\n').count() + 1;
            let line_start = before.rfind('\n').map_or(0, |i| i + 1);
            let col = start - line_start + 1;
            let line_text = text[line_start..].lines().next().unwrap_or("").trim();
            // The table the line sits in, e.g. `[[mesh]]` (the n-th one) or `[light]`.
            let section = before[..line_start]
                .lines()
                .rev()
                .map(str::trim)
                .find(|l| l.starts_with('['));
            let section = match section {
                Some(h) if h.starts_with("[[") => {
                    let n = before[..line_start]
                        .lines()
                        .filter(|l| l.trim() == h)
                        .count();
                    format!("{h} #{n} ")
                }
                Some(h) => format!("{h} "),
                None => String::new(),
            };
            let at = if line_text.is_empty() || line_text.starts_with('[') {
                String::new()
            } else {
                format!("{section}{line_text}: ")
            };
            format!("{lead}at line {line}, column {col}: {at}{msg}")
        }
        None => format!("{lead}{msg}").trim().to_string(),
    }
}

/// A mesh's albedo: reflectance, so each component in [0, 1] (more would reflect more light than
/// arrives).
pub(super) fn albedo(origin: &str, k: usize, v: [f32; 3]) -> Result<Vec3> {
    if !v.iter().all(|c| (0.0..=1.0).contains(c)) {
        return Err(Error::scene(
            origin,
            format!(
                "mesh {} albedo = {v:?}: each component must be in [0, 1]",
                k + 1
            ),
        ));
    }
    Ok(Vec3::from(v))
}

pub(crate) fn build(def: SceneDef, origin: &str, dirs: MeshDirs) -> Result<Scene> {
    let camera = camera(origin, &def.camera)?;
    let environment = match &def.environment {
        Some(e) => Some(crate::scene::environment::scene::build(e, origin, dirs)?),
        None => None,
    };
    let (light, emitter) = match (&def.light, &environment) {
        (Some(l), _) => super::emitter_def::build(l, origin)?,
        (None, Some(_)) => (None, Emitter::Rect),
        (None, None) => {
            return Err(Error::scene(
                origin,
                "the scene has no [light] and no [environment]: give one",
            ))
        }
    };
    let render = render_settings(origin, &def.render)?;
    if def.meshes.is_empty() {
        return Err(Error::scene(origin, "the scene has no [[mesh]]"));
    }
    let (mut meshes, mut warnings) = (Vec::new(), Vec::new());
    for (k, m) in def.meshes.iter().enumerate() {
        let albedo = albedo(origin, k, m.albedo)?;
        let (verts, idx, open_edges) = mesh::instantiate(m, k, origin, dirs)?;
        if open_edges > 0 && render.cull != CullMode::None {
            // Through an open mesh's gaps the light sees back faces; culled, they let light through
            // that the reference's rays find blocked (`teapot`: RMSE 0.0324 against 0.0102).
            warnings.push(format!(
                "warning: {origin}: mesh {} ({}) is open ({open_edges} boundary edges) and the shadow raster culls {} faces: light can pass through its gaps; set cull = \"none\" (docs/scene-format.md)",
                k + 1,
                m.file.as_deref().unwrap_or("?"),
                if render.cull == CullMode::Back { "back" } else { "front" }
            ));
        }
        meshes.push((verts, idx, albedo.to_array()));
    }
    let parts = Parts {
        name: def.name,
        description: def.description,
        stated_triangles: def.triangles,
        camera,
        light,
        emitter,
        environment,
        render,
    };
    let mut scene = assemble(parts, meshes, origin)?;
    for w in &warnings {
        crate::progress::notice(w);
    }
    scene.warnings = warnings;
    Ok(scene)
}

/// A scene's checked parts besides its meshes: what [`assemble`] joins to the meshes.
pub(crate) struct Parts {
    pub(crate) name: Option<String>,
    pub(crate) description: Option<String>,
    /// Triangle count the author states; checked against the meshes.
    pub(crate) stated_triangles: Option<u64>,
    pub(crate) camera: Camera,
    /// `None`: a panorama lights the scene and the light is a nominal square above the meshes, or
    /// the emitter is not a rectangle and the light is its stand-in.
    pub(crate) light: Option<AreaLight>,
    pub(crate) emitter: Emitter,
    pub(crate) environment: Option<crate::scene::environment::Environment>,
    pub(crate) render: RenderSettings,
}

/// The checked `[camera]`.
pub(crate) fn camera(origin: &str, def: &CameraDef) -> Result<Camera> {
    let camera = Camera {
        eye: finite(origin, "camera.eye", def.eye)?,
        target: finite(origin, "camera.target", def.target)?,
        up: finite(origin, "camera.up", def.up)?,
        fov_y_deg: def.fov_y_deg,
    };
    let fov = camera.fov_y_deg;
    if !(MIN_FOV_DEG..=MAX_FOV_DEG).contains(&fov) {
        return Err(Error::scene(
            origin,
            format!("camera.fov_y_deg = {fov:?}: must be in [{MIN_FOV_DEG}, {MAX_FOV_DEG}] degrees (near 180 the whole scene shrinks to a point; 180 has no projection)"),
        ));
    }
    let view_dir = camera.target - camera.eye;
    let (eye, target, up) = (
        camera.eye.to_array(),
        camera.target.to_array(),
        camera.up.to_array(),
    );
    if view_dir.length()
        < 1e-9
            * camera
                .eye
                .abs()
                .max(camera.target.abs())
                .max_element()
                .max(1.0)
    {
        return Err(Error::scene(origin, format!("camera.eye = {eye:?} and camera.target = {target:?} coincide: the camera has no view direction")));
    }
    let up_dir = camera.up.normalize_or_zero();
    if up_dir == Vec3::ZERO {
        return Err(Error::scene(origin, format!("camera.up = {up:?}: has no direction; give the way up on screen, e.g. [0.0, 1.0, 0.0]")));
    }
    if view_dir.normalize().cross(up_dir).length() < 1e-6 {
        return Err(Error::scene(
            origin,
            format!("camera.up = {up:?} is parallel to the view direction (camera.target − camera.eye = {:?}): give an up across it", view_dir.to_array()),
        ));
    }
    Ok(camera)
}

/// The camera's vertical field of view, in degrees: near 180 the scene shrinks to a point, and at
/// tiny angles the projection's scale (1/tan) overflows f32 with coordinates of ±MAX_COORDINATE.
pub(crate) const MIN_FOV_DEG: f32 = 0.01;
pub(crate) const MAX_FOV_DEG: f32 = 179.0;

/// Smallest shadow map per side: below it a map holds a handful of texels (1² or 3² maps were
/// accepted and rendered nonsense); the failure gallery's smallest map is the same.
pub(crate) const MIN_SHADOW_MAP_SIZE: u32 = 16;

/// The checked `[render]` table, with a hybrid map's raster size in `shadow_map_size`.
pub(crate) fn render_settings(origin: &str, r: &RenderSettings) -> Result<RenderSettings> {
    for (key, v) in [("render.width", r.width), ("render.height", r.height)] {
        if v == 0 {
            return Err(Error::scene(origin, format!("{key} must be at least 1")));
        }
    }
    if r.shadow_map_size < MIN_SHADOW_MAP_SIZE {
        return Err(Error::scene(
            origin,
            format!(
                "render.shadow_map_size = {}: must be at least {MIN_SHADOW_MAP_SIZE}",
                r.shadow_map_size
            ),
        ));
    }
    if r.shadow_map_budget_mib == 0 {
        return Err(Error::scene(
            origin,
            "render.shadow_map_budget_mib must be at least 1",
        ));
    }
    let b = r.bias;
    let numbers = [
        ("render.bias.constant", b.constant),
        ("render.bias.slope", b.slope),
        ("render.bias.normal_offset", b.normal_offset),
        ("render.bias.max_slope", b.max_slope),
        ("render.ambient", r.ambient),
    ];
    if let Some((key, v)) = numbers.iter().find(|(_, v)| !v.is_finite()) {
        return Err(Error::scene(
            origin,
            format!("{key} = {v}: must be a finite number"),
        ));
    }
    // A negative bias moves the depth test in front of the receiver: every surface shadows itself
    // (a constant of -1 put 98% of pixels in shadow). No use of the method needs it; 0 turns a term off.
    if let Some((key, v)) = numbers[..4].iter().find(|(_, v)| *v < 0.0) {
        return Err(Error::scene(
            origin,
            format!(
                "{key} = {v}: must be >= 0 (a negative bias shadows every surface with itself)"
            ),
        ));
    }
    if !(0.0..=1.0).contains(&r.ambient) {
        return Err(Error::scene(
            origin,
            format!("render.ambient must be in [0, 1], got {}", r.ambient),
        ));
    }
    let mut render = r.clone();
    if render.maps == MapKind::Hybrid {
        let hy = render.hybrid;
        if !(1..=2).contains(&hy.levels) {
            return Err(Error::scene(
                origin,
                format!("render.hybrid.levels = {}: use 1 or 2", hy.levels),
            ));
        }
        if hy.base < MIN_SHADOW_MAP_SIZE {
            return Err(Error::scene(
                origin,
                format!(
                    "render.hybrid.base = {}: must be at least {MIN_SHADOW_MAP_SIZE}",
                    hy.base
                ),
            ));
        }
        if hy.base % (1 << hy.levels) != 0 {
            return Err(Error::scene(
                origin,
                format!(
                    "render.hybrid.base = {}: must be a positive multiple of 2^levels = {}",
                    hy.base,
                    1 << hy.levels
                ),
            ));
        }
        if !(hy.eps.is_finite() && hy.eps >= 0.0) {
            return Err(Error::scene(
                origin,
                format!(
                    "render.hybrid.eps = {}: must be a finite number >= 0",
                    hy.eps
                ),
            ));
        }
        // The raster (and every lookup's texel grid) is the full resolution.
        render.shadow_map_size = hy.base;
    }
    Ok(render)
}

/// Joins checked parts and meshes (vertices, indices, albedo; material indices are assigned here
/// in mesh order) into a scene: bounds, the light's side, the stated triangle count, the view.
pub(crate) fn assemble(
    parts: Parts,
    meshes: Vec<(Vec<Vertex>, Vec<u32>, [f32; 3])>,
    origin: &str,
) -> Result<Scene> {
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    let mut albedos = Vec::new();
    for (verts, idx, albedo) in meshes {
        let base = vertices.len() as u32;
        vertices.extend(verts.into_iter().map(|mut v| {
            v.material = albedos.len() as u32;
            v
        }));
        indices.extend(idx.into_iter().map(|i| i + base));
        albedos.push(albedo);
    }
    let mut min = Vec3::splat(f32::INFINITY);
    let mut max = Vec3::splat(f32::NEG_INFINITY);
    for v in &vertices {
        min = min.min(Vec3::from(v.position));
        max = max.max(Vec3::from(v.position));
    }
    let bounds = Bounds { min, max };
    let light = match (parts.emitter.stand_in(&bounds), parts.light) {
        (Some(light), _) | (None, Some(light)) => {
            let lit = super::light_checks::Lit {
                bounds: &bounds,
                eye: parts.camera.eye,
                vertices: &vertices,
                indices: &indices,
            };
            super::light_checks::check(origin, &light, &parts.emitter, &lit)?;
            light
        }
        (None, None) => crate::scene::environment::scene::light_above(min, max),
    };
    if let Some(stated) = parts.stated_triangles {
        let got = indices.len() as u64 / 3;
        if stated != got {
            return Err(Error::scene(
                origin,
                format!("states triangles = {stated} but its meshes have {got}"),
            ));
        }
    }
    if parts.name.as_deref().is_some_and(|n| n.trim().is_empty()) {
        return Err(Error::scene(origin, format!("name = {:?}: a scene's name must not be empty (leave `name` out to use the file's)", parts.name.unwrap_or_default())));
    }
    let scene = Scene {
        name: parts
            .name
            .unwrap_or_else(|| origin.trim_start_matches("builtin:").to_string()),
        description: parts.description.unwrap_or_default(),
        origin: origin.to_string(),
        camera: parts.camera,
        light,
        emitter: parts.emitter,
        environment: parts.environment,
        render: parts.render,
        vertices,
        indices,
        albedos,
        bounds,
        warnings: Vec::new(),
    };
    if scene.bounds_outside_view() {
        return Err(scene.nothing_visible());
    }
    Ok(scene)
}
