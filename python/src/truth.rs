//! The ground truth, metrics and compare, through the lab's own functions: `reference` reads and
//! fills the same cache as `penumbra reference`, `metrics` is compare's judge, `compare` is the
//! study `penumbra compare` runs (without writing its folder).

use crate::progress::Lines;
use crate::scene::Scene;
use numpy::{PyArray2, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use penumbra_lab::gpu::GpuContext;
use penumbra_lab::methods::Method;
use penumbra_lab::record::judge::Judge;
use penumbra_lab::record::Provenance;
use penumbra_lab::reference::truth::{self, Cache};
use penumbra_lab::render::gbuffer::GBufferCpu;
use penumbra_lab::scene;
use penumbra_lab::studies::compare::{self, methods_list, CompareJob};
use pyo3::prelude::*;
use std::sync::Arc;

/// The reference of one scene: V as an array (`numpy.asarray(ref)`, `ref.values`), and what `metrics` judges against.
#[pyclass(module = "penumbra", frozen)]
pub struct Reference {
    scene: Arc<scene::Scene>,
    g: GBufferCpu,
    judge: Judge,
    mode: String,
    cache_file: Option<String>,
    seconds: Option<f64>,
}

fn parse_mode(reference: &str, samples: u32) -> PyResult<penumbra_lab::reference::ReferenceMode> {
    truth::parse_mode(reference, samples).map_err(crate::to_py)
}

/// The ground truth of `scene`, traced on the CPU or read from the cache `penumbra reference` fills.
///
/// Args:
///     scene: the scene.
///     samples: `continuous`: samples × samples stratified points per pixel (1..=256).
///     mode: `continuous`, `lattice` (the 289 lattice points) or `point[:S,T]` (one light point).
///     no_cache: trace without the cache: nothing read or stored.
///     adapter: the GPU adapter for the G-buffer, as for `Renderer`.
///     progress: `None`: a line on a terminal's stderr, or in a Jupyter cell; `True`: on Python's
///         `sys.stderr`; `False`: nothing; a callable: called with each line.
///
/// Returns:
///     The reference: V as float32 (height, width), NaN on the background.
///
/// Raises:
///     PenumbraError: a bad mode or sample count.
///     GpuError: the device failed.
#[pyfunction]
#[pyo3(signature = (scene, samples=32, mode="continuous", no_cache=false, adapter=None, progress=None))]
pub fn reference(
    py: Python<'_>,
    scene: &Scene,
    samples: u32,
    mode: &str,
    no_cache: bool,
    adapter: Option<&str>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<Reference> {
    let lines = Lines::from_arg(py, progress)?;
    let mode = parse_mode(mode, samples)?;
    let ctx: Arc<GpuContext> = crate::context::get(py, adapter)?;
    let s = scene.inner.clone();
    let (g, image) = py
        .detach(|| truth::for_scene(&ctx, &s, mode, &Cache::default_for(no_cache)))
        .map_err(crate::to_py)?;
    lines.line(&compare::reference_line(&image, g.geometry_count()));
    let judge = Judge::new(&s, &g, image.values.clone());
    Ok(Reference {
        mode: truth::mode_label(&image.mode),
        cache_file: image.cache_file.as_ref().map(|p| p.display().to_string()),
        seconds: image.trace.map(|t| t.seconds),
        scene: s,
        g,
        judge,
    })
}

#[pymethods]
impl Reference {
    /// V of the reference, float32 of shape (height, width), NaN on the background.
    #[getter]
    fn values<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        crate::renderer::visibility_array(py, &self.judge.reference, &self.g)
    }

    #[pyo3(signature = (dtype=None, copy=None))]
    fn __array__<'py>(
        &self,
        py: Python<'py>,
        dtype: Option<Bound<'py, PyAny>>,
        copy: Option<bool>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let _ = copy;
        let v = self.values(py)?.into_any();
        match dtype {
            Some(d) => v.call_method1("astype", (d,)),
            None => Ok(v),
        }
    }

    #[getter]
    fn shape(&self) -> (u32, u32) {
        (self.g.height, self.g.width)
    }

    /// The mode's label, as in run records (`continuous 32x32`).
    #[getter]
    fn mode(&self) -> &str {
        &self.mode
    }

    /// The cache file it was read from or written to.
    #[getter]
    fn cache_file(&self) -> Option<&str> {
        self.cache_file.as_deref()
    }

    /// Tracing seconds; `None` when it came from the cache.
    #[getter]
    fn seconds(&self) -> Option<f64> {
        self.seconds
    }

    #[getter]
    fn geometry_pixels(&self) -> usize {
        self.judge.geometry_pixels()
    }

    fn __repr__(&self) -> String {
        format!(
            "Reference({:?}, {}x{}, {})",
            self.scene.name, self.g.width, self.g.height, self.mode
        )
    }
}

/// The figures `penumbra compare` reports for V against the reference, over its geometry pixels.
///
/// Args:
///     v: V, float of shape (height, width) as `Renderer.render` returns it (background ignored).
///     reference: the reference of the same scene.
///
/// Returns:
///     `rmse`, `mae`, `max_abs`, `psnr` (None when identical), `ssim`, `flip_mean`, `flip_p95`,
///     `flip_p99`, `penumbra_rmse`, `bad_pixel_share`, `nan_count`, `pixels`, ... as floats and ints.
///
/// Raises:
///     PenumbraError: V's shape is not the reference's.
#[pyfunction]
pub fn metrics<'py>(
    py: Python<'py>,
    v: &Bound<'py, PyAny>,
    reference: &Reference,
) -> PyResult<Bound<'py, PyAny>> {
    let a = py
        .import("numpy")?
        .call_method1("ascontiguousarray", (v, "float32"))?;
    let a: PyReadonlyArrayDyn<f32> = a.extract()?;
    let (h, w) = (reference.g.height as usize, reference.g.width as usize);
    if a.shape() != [h, w] {
        return Err(crate::PenumbraError::new_err(format!(
            "metrics: V has shape {:?}, the reference ({}) is ({h}, {w})",
            a.shape(),
            reference.scene.name
        )));
    }
    // Background pixels as the engine leaves them (0): they are outside every figure, but shading reads them.
    let values: Vec<f32> = a
        .as_slice()?
        .iter()
        .enumerate()
        .map(|(i, &x)| if reference.judge.mask[i] { x } else { 0.0 })
        .collect();
    let judged = py
        .detach(|| {
            reference
                .judge
                .judge_values(&reference.scene, &reference.g, &values)
        })
        .map_err(crate::to_py)?;
    crate::json_to_py(
        py,
        &serde_json::to_value(&judged.metrics)
            .map_err(|e| crate::PenumbraError::new_err(e.to_string()))?,
    )
}

/// `penumbra compare` on `scene`; `penumbra.compare` wraps it (its rows are a `Rows`).
#[pyfunction]
#[pyo3(signature = (scene, methods, repeats=3, samples=32, reference="continuous", no_cache=false, adapter=None, progress=None))]
#[pyo3(name = "compare")]
#[allow(clippy::too_many_arguments)]
pub fn compare_methods<'py>(
    py: Python<'py>,
    scene: &Scene,
    methods: &Bound<'py, PyAny>,
    repeats: u32,
    samples: u32,
    reference: &str,
    no_cache: bool,
    adapter: Option<&str>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let lines = Lines::from_arg(py, progress)?;
    let values: Vec<String> = match methods.extract::<String>() {
        Ok(one) => vec![one],
        Err(_) => methods.extract()?,
    };
    let specs = methods_list::split_specs(&values).map_err(crate::to_py)?;
    let methods: Vec<Method> = methods_list::parse_methods(&specs).map_err(crate::to_py)?;
    let mode = parse_mode(reference, samples)?;
    if repeats == 0 || repeats > 1000 {
        return Err(crate::PenumbraError::new_err(format!(
            "repeats must be in 1..=1000, got {repeats}"
        )));
    }
    let s = scene.inner.clone();
    penumbra_lab::methods::check_lights(&s, &methods).map_err(crate::engine)?;
    let ctx = crate::context::get(py, adapter)?;
    let provenance = vec![Provenance::of_scene("compare", &s, &scene.sets, None); methods.len()];
    let outcome = py
        .detach(|| -> penumbra_lab::Result<_> {
            penumbra_lab::methods::sizes::check_all(&ctx, &s, &methods)?;
            let job = CompareJob {
                scene: &s,
                methods,
                repeats,
                reference: mode,
                cache: Cache::default_for(no_cache),
                provenance,
                pictures: false,
                certify: None,
            };
            compare::run(&ctx, &job, &|line: &str| lines.line(line))
        })
        .map_err(crate::to_py)?;
    let mut rows = serde_json::to_value(&outcome.rows)
        .map_err(|e| crate::PenumbraError::new_err(e.to_string()))?;
    // `images` names files of compare's folder, which this call does not write.
    for row in rows.as_array_mut().into_iter().flatten() {
        row.as_object_mut().map(|r| r.remove("images"));
    }
    crate::json_to_py(py, &rows)
}

/// Channel 0 of an EXR as float32 of shape (height, width): V as `penumbra render` and `compare` write it (0 on the background).
///
/// Args:
///     path: a `visibility.exr` or `reference.exr`.
///
/// Returns:
///     V, float32 (height, width).
///
/// Raises:
///     PenumbraError: the file is missing or not an EXR.
#[pyfunction]
pub fn read_exr<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    use numpy::{IntoPyArray, PyArrayMethods};
    let img = py
        .detach(|| image::open(&path))
        .map_err(|e| crate::PenumbraError::new_err(format!("{}: {e}", path.display())))?
        .to_rgb32f();
    let (w, h) = (img.width() as usize, img.height() as usize);
    img.pixels()
        .map(|p| p[0])
        .collect::<Vec<f32>>()
        .into_pyarray(py)
        .reshape([h, w])
}
