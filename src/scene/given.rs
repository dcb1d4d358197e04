//! Scenes from meshes a caller hands over in memory (the embedding API, src/api.rs), checked by the
//! same rules as a scene file: one set of checks, one way to assemble a [`Scene`].

use super::coords::finite;
use super::emitter_def::{build, build_light, LightDef};
use super::format::{self, CameraDef, Parts};
use super::mesh::{smooth_normals, Vertex, MAX_SCENE_TRIANGLES};
use super::model::{Camera, Scene};
use super::overrides::apply_overrides;
use super::settings::RenderSettings;
use crate::scene::light::AreaLight;
use crate::{Error, Result};
use glam::Vec3;

/// One mesh in world space, as a caller gives it.
pub struct GivenMesh<'a> {
    pub positions: &'a [[f32; 3]],
    /// Three indices per triangle, counter-clockwise seen from the front.
    pub indices: &'a [u32],
    /// Per-vertex normals; `None`: area-weighted smooth normals, as for a mesh file without them.
    pub normals: Option<&'a [[f32; 3]]>,
    pub albedo: [f32; 3],
}

/// Render settings from `--set`-style pairs over the defaults (the keys of `penumbra render --set`).
pub fn settings_from_pairs(origin: &str, pairs: &[(String, String)]) -> Result<RenderSettings> {
    let settings = |pairs: &[(String, String)]| -> Result<std::result::Result<RenderSettings, toml::de::Error>> {
        let mut table = toml::Table::new();
        apply_overrides(&mut table, pairs, origin)?;
        Ok(match table.remove("render") {
            Some(v) => v.try_into::<RenderSettings>(),
            None => Ok(RenderSettings::default()),
        })
    };
    let render = settings(pairs)?.map_err(|e| {
        let why = e.message().trim().to_string();
        // The pair at fault is the one refused alone.
        match pairs
            .iter()
            .find(|p| matches!(settings(std::slice::from_ref(p)), Ok(Err(_))))
        {
            Some((k, v)) => Error::Setting {
                origin: Some(origin.to_string()),
                key: k.clone(),
                value: Some(v.clone()),
                why,
            },
            None => Error::Param(format!("{origin}: render setting: {why}")),
        }
    })?;
    format::render_settings(origin, &render)
}

fn camera_def(c: &Camera) -> CameraDef {
    CameraDef {
        eye: c.eye.to_array(),
        target: c.target.to_array(),
        up: c.up.to_array(),
        fov_y_deg: c.fov_y_deg,
    }
}

fn light_def(l: &AreaLight) -> LightDef {
    LightDef {
        center: Some(l.center.to_array()),
        edge_u: Some(l.edge_u.to_array()),
        edge_v: Some(l.edge_v.to_array()),
        ..LightDef::default()
    }
}

impl Scene {
    /// A scene of `meshes` under a rectangular light; `render` comes from [`settings_from_pairs`].
    pub(crate) fn from_meshes(
        origin: &str,
        camera: &Camera,
        light: &AreaLight,
        render: RenderSettings,
        meshes: &[GivenMesh],
    ) -> Result<Scene> {
        Self::from_meshes_lit(
            origin,
            camera,
            || {
                Ok((
                    Some(build_light(&light_def(light), origin)?),
                    crate::scene::Emitter::Rect,
                ))
            },
            render,
            meshes,
        )
    }

    /// A scene of `meshes` under a light of any kind, given as a scene file's `[light]` table
    /// (docs/lights.md: `kind = "disk"`, `center`, `normal`, `radius`, …) and checked as one.
    pub fn from_meshes_with_light(
        origin: &str,
        camera: &Camera,
        light: toml::Table,
        render: RenderSettings,
        meshes: &[GivenMesh],
    ) -> Result<Scene> {
        let light = || {
            let def: LightDef =
                toml::Value::Table(light)
                    .try_into()
                    .map_err(|e: toml::de::Error| {
                        Error::scene(origin, format!("light: {}", e.message().trim()))
                    })?;
            build(&def, origin)
        };
        Self::from_meshes_lit(origin, camera, light, render, meshes)
    }

    /// The camera is checked first, then the light (`light` builds it), then the meshes.
    fn from_meshes_lit(
        origin: &str,
        camera: &Camera,
        light: impl FnOnce() -> Result<(Option<AreaLight>, crate::scene::Emitter)>,
        render: RenderSettings,
        meshes: &[GivenMesh],
    ) -> Result<Scene> {
        let camera = format::camera(origin, &camera_def(camera))?;
        let (light, emitter) = light()?;
        if meshes.is_empty() {
            return Err(Error::scene(origin, "the scene has no mesh"));
        }
        let (mut vertex_total, mut triangle_total) = (0u64, 0u64);
        let mut parts = Vec::with_capacity(meshes.len());
        for (k, m) in meshes.iter().enumerate() {
            let what = |field: &str| format!("mesh {} {field}", k + 1);
            let albedo = format::albedo(origin, k, m.albedo)?;
            if m.indices.is_empty() || m.indices.len() % 3 != 0 {
                return Err(Error::scene(
                    origin,
                    format!(
                        "mesh {}: {} indices: give three per triangle, at least one triangle",
                        k + 1,
                        m.indices.len()
                    ),
                ));
            }
            if let Some(i) = m.indices.iter().find(|&&i| i as usize >= m.positions.len()) {
                return Err(Error::scene(
                    origin,
                    format!(
                        "mesh {}: index {i} is out of range ({} positions)",
                        k + 1,
                        m.positions.len()
                    ),
                ));
            }
            vertex_total += m.positions.len() as u64;
            triangle_total += m.indices.len() as u64 / 3;
            if vertex_total > u32::MAX as u64 || triangle_total > MAX_SCENE_TRIANGLES {
                return Err(Error::scene(
                    origin,
                    format!("the meshes exceed {MAX_SCENE_TRIANGLES} triangles or 2^32 vertices"),
                ));
            }
            let positions = m
                .positions
                .iter()
                .map(|p| finite(origin, &what("position"), *p))
                .collect::<Result<Vec<Vec3>>>()?;
            let normals = match m.normals {
                Some(n) if n.len() != positions.len() => {
                    return Err(Error::scene(
                        origin,
                        format!(
                            "mesh {}: {} normals for {} positions",
                            k + 1,
                            n.len(),
                            positions.len()
                        ),
                    ));
                }
                Some(n) => n
                    .iter()
                    .map(|v| finite(origin, &what("normal"), *v).map(Vec3::normalize_or_zero))
                    .collect::<Result<Vec<Vec3>>>()?,
                None => smooth_normals(&positions, m.indices),
            };
            let vertices = positions
                .iter()
                .zip(&normals)
                .map(|(p, n)| Vertex {
                    position: p.to_array(),
                    normal: n.to_array(),
                    material: 0,
                })
                .collect();
            parts.push((vertices, m.indices.to_vec(), albedo.to_array()));
        }
        let scene_parts = Parts {
            name: None,
            description: None,
            stated_triangles: None,
            camera,
            light,
            emitter,
            environment: None,
            render,
        };
        format::assemble(scene_parts, parts, origin)
    }

    /// `camera` checked as a scene file's `[camera]` is, and against these meshes' bounds.
    pub(crate) fn check_camera(&self, camera: &Camera) -> Result<Camera> {
        let camera = format::camera(&self.origin, &camera_def(camera))?;
        if self.bounds_outside(&camera) {
            return Err(self.nothing_visible_from(&camera));
        }
        Ok(camera)
    }

    /// `light` checked as a scene file's `[light]` is, and against these meshes (src/scene/light_checks.rs).
    pub(crate) fn check_light(&self, light: &AreaLight) -> Result<AreaLight> {
        let light = build_light(&light_def(light), &self.origin)?;
        let lit = super::light_checks::Lit {
            bounds: &self.bounds,
            eye: self.camera.eye,
            vertices: &self.vertices,
            indices: &self.indices,
        };
        super::light_checks::check(&self.origin, &light, &crate::scene::Emitter::Rect, &lit)?;
        Ok(light)
    }
}
