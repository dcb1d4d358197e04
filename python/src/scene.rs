//! `penumbra.Scene`: a checked scene, loaded by name or TOML path as `--scene` takes it, or built
//! from numpy vertex and index arrays with a camera and a rectangular light.

use glam::Vec3;
use numpy::{PyReadonlyArrayDyn, PyUntypedArrayMethods};
use penumbra_lab::scene::{self, Camera, GivenMesh};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use std::sync::Arc;

/// A checked scene: meshes, camera, area light and render settings.
#[pyclass(module = "penumbra", frozen)]
pub struct Scene {
    pub inner: Arc<scene::Scene>,
    /// The render settings given, as `KEY=VALUE` (the provenance of compare's rows).
    pub sets: Vec<String>,
}

impl Scene {
    pub fn new(inner: scene::Scene, pairs: &[(String, String)]) -> Scene {
        Scene {
            inner: Arc::new(inner),
            sets: pairs.iter().map(|(k, v)| format!("{k}={v}")).collect(),
        }
    }
}

/// `obj` as a C-contiguous array of `dtype` (anything numpy accepts: lists, other dtypes).
fn contiguous<'py>(obj: &Bound<'py, PyAny>, dtype: &str) -> PyResult<Bound<'py, PyAny>> {
    obj.py()
        .import("numpy")?
        .call_method1("ascontiguousarray", (obj, dtype))
}

fn triples(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[f32; 3]>> {
    let a = contiguous(obj, "float32")?;
    let a: PyReadonlyArrayDyn<f32> = a.extract()?;
    if a.ndim() != 2 || a.shape()[1] != 3 {
        return Err(crate::PenumbraError::new_err(format!(
            "{what}: expected an (N, 3) array, got shape {:?}",
            a.shape()
        )));
    }
    Ok(a.as_slice()?
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect())
}

fn vec3(d: &Bound<'_, PyDict>, key: &str, what: &str) -> PyResult<Option<Vec3>> {
    let Some(v) = d.get_item(key)? else {
        return Ok(None);
    };
    let v: Vec<f32> = contiguous(&v, "float32")?
        .call_method0("ravel")?
        .call_method0("tolist")?
        .extract()?;
    match v[..] {
        [x, y, z] => Ok(Some(Vec3::new(x, y, z))),
        _ => Err(crate::PenumbraError::new_err(format!(
            "{what}.{key}: expected three numbers, got {}",
            v.len()
        ))),
    }
}

fn required(d: &Bound<'_, PyDict>, key: &str, what: &str) -> PyResult<Vec3> {
    vec3(d, key, what)?
        .ok_or_else(|| crate::PenumbraError::new_err(format!("{what}: `{key}` is missing")))
}

/// A light dict (numpy arrays allowed) as the scene file's `[light]` table it stands for.
fn light_table(light: &Bound<'_, PyDict>) -> PyResult<toml::Table> {
    let plain = PyDict::new(light.py());
    for (k, v) in light.iter() {
        let v = if v.hasattr("tolist")? {
            v.call_method0("tolist")?
        } else {
            v
        };
        plain.set_item(k, v)?;
    }
    let text: String = light
        .py()
        .import("json")?
        .call_method1("dumps", (plain,))?
        .extract()?;
    let bad = |e: String| crate::PenumbraError::new_err(format!("light: {e}"));
    let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
    match toml::Value::try_from(json).map_err(|e| bad(e.to_string()))? {
        toml::Value::Table(t) => Ok(t),
        _ => Err(bad("expected a dict".into())),
    }
}

#[pymethods]
impl Scene {
    /// A built-in scene by name or a scene TOML file, with render settings.
    ///
    /// Args:
    ///     name_or_path: a built-in scene (`penumbra scenes` lists them) or the path of a scene TOML file.
    ///     **settings: render settings by the keys of `penumbra render --set`: `resolution=128`,
    ///         `shadow_map_size=1024`, `cull="none"`, `ambient=0.1`, ... (`True` is `true`).
    ///
    /// Returns:
    ///     The scene, checked as the command line checks it.
    ///
    /// Raises:
    ///     PenumbraError: no such scene, a malformed file, a missing mesh, an unknown setting or a
    ///         value it refuses (named as its keyword: `cull='sideways'`).
    #[staticmethod]
    #[pyo3(signature = (name_or_path, **settings))]
    fn load(
        py: Python<'_>,
        name_or_path: &str,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Scene> {
        let pairs = crate::pairs(settings)?;
        let inner = py
            .detach(|| scene::Scene::load(name_or_path, &pairs))
            .map_err(crate::engine)?;
        Ok(Scene::new(inner, &pairs))
    }

    /// A scene from meshes in memory, checked as a scene file is.
    ///
    /// Args:
    ///     meshes: `(positions, indices)` or `(positions, indices, albedo)` per mesh: positions
    ///         float (N, 3), indices int (M, 3) or (3M,), counter-clockwise seen from the front,
    ///         albedo three floats (default 0.8 grey).
    ///     camera: `eye`, `target`, `fov_y_deg` and optionally `up` (three floats each).
    ///     light: the scene file's `[light]` table: a rectangle `{center, edge_u, edge_v}` or any
    ///         kind of docs/lights.md (`{"kind": "disk", "center": ..., "normal": ..., "radius": ...}`).
    ///     **settings: render settings, as for `Scene.load`.
    ///
    /// Returns:
    ///     The scene; its errors name `embedded scene`.
    ///
    /// Raises:
    ///     PenumbraError: a malformed mesh, camera, light or setting.
    #[staticmethod]
    #[pyo3(signature = (meshes, camera, light, **settings))]
    fn from_meshes(
        py: Python<'_>,
        meshes: Vec<Bound<'_, PyTuple>>,
        camera: &Bound<'_, PyDict>,
        light: &Bound<'_, PyDict>,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Scene> {
        let mut owned = Vec::new();
        for (k, m) in meshes.iter().enumerate() {
            let what = format!("mesh {}", k + 1);
            if !(2..=3).contains(&m.len()) {
                return Err(crate::PenumbraError::new_err(format!(
                    "{what}: give (positions, indices) or (positions, indices, albedo)"
                )));
            }
            let positions = triples(&m.get_item(0)?, &format!("{what} positions"))?;
            let indices: PyReadonlyArrayDyn<u32> =
                contiguous(&m.get_item(1)?, "uint32")?.extract()?;
            let indices = indices.as_slice()?.to_vec();
            let albedo = if m.len() == 3 {
                m.get_item(2)?.extract::<[f32; 3]>()?
            } else {
                [0.8; 3]
            };
            owned.push((positions, indices, albedo));
        }
        let given: Vec<GivenMesh> = owned
            .iter()
            .map(|(p, i, a)| GivenMesh {
                positions: p,
                indices: i,
                normals: None,
                albedo: *a,
            })
            .collect();
        let up = vec3(camera, "up", "camera")?.unwrap_or(Vec3::Y);
        let fov_y_deg: f32 = camera
            .get_item("fov_y_deg")?
            .ok_or_else(|| crate::PenumbraError::new_err("camera: `fov_y_deg` is missing"))?
            .extract()?;
        let camera = Camera {
            eye: required(camera, "eye", "camera")?,
            target: required(camera, "target", "camera")?,
            up,
            fov_y_deg,
        };
        let light = light_table(light)?;
        let pairs = crate::pairs(settings)?;
        const ORIGIN: &str = "embedded scene";
        let render = scene::settings_from_pairs(ORIGIN, &pairs).map_err(crate::engine)?;
        let inner = py
            .detach(|| scene::Scene::from_meshes_with_light(ORIGIN, &camera, light, render, &given))
            .map_err(crate::engine)?;
        Ok(Scene::new(inner, &pairs))
    }

    #[getter]
    fn name(&self) -> &str {
        &self.inner.name
    }

    /// The file or `builtin:NAME` every error names.
    #[getter]
    fn origin(&self) -> &str {
        &self.inner.origin
    }

    #[getter]
    fn width(&self) -> u32 {
        self.inner.render.width
    }

    #[getter]
    fn height(&self) -> u32 {
        self.inner.render.height
    }

    #[getter]
    fn triangles(&self) -> usize {
        self.inner.triangle_count()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({:?}, {}x{}, {} triangles)",
            self.inner.name,
            self.inner.render.width,
            self.inner.render.height,
            self.inner.triangle_count()
        )
    }
}
