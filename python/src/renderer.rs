//! `penumbra.Renderer`: methods built once per scene and kept, so repeated renders cost what
//! `ShadowRenderer::render` costs in Rust.

use crate::record::{Pending, Record};
use crate::scene::Scene;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyArrayMethods};
use penumbra_lab::frame::certify::{FrameCertifier, ProxyKind};
use penumbra_lab::frame::{self, FrameOptions};
use penumbra_lab::gpu::timing::TimingMode;
use penumbra_lab::gpu::GpuContext;
use penumbra_lab::methods::Method;
use penumbra_lab::record::run_files::VSum;
use penumbra_lab::scene;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// A built method. Its renderer shares the context and the scene with the owning [`Renderer`]
/// (`Arc`s), so it borrows nothing; the `Mutex` in `Renderer` lets one thread at a time render.
struct Built {
    renderer: frame::Renderer<'static>,
    /// Shared with the records of its frames.
    method: Arc<Method>,
}

/// A method spec and its parameters as `render` received them.
type Request = (String, Vec<(String, String)>);

/// Renders methods on one scene, each built once and kept: repeated renders reuse its pipelines and buffers.
///
/// Args:
///     scene: the scene to render.
///     adapter: a GPU adapter's name or part of one, as `penumbra --adapter` takes it; `None`
///         picks as the command line does (`WGPU_ADAPTER_NAME`, else the best adapter).
///     reuse: each method keeps its shadow maps between `render` calls, which then rasterize
///         only what changed (nothing, on one scene; V is the same bit for bit; docs/reuse.md).
///
/// Raises:
///     GpuError: no adapter matches, or none is usable.
///     PenumbraError: `WGPU_BACKEND` names no backend.
#[pyclass(module = "penumbra", frozen)]
pub struct Renderer {
    built: Mutex<HashMap<String, Built>>,
    /// The label each request parsed to: a repeated render skips the parse and the light check
    /// (only accepted requests are kept, so a refused one is refused with its message again).
    labels: Mutex<HashMap<Request, String>>,
    ctx: Arc<GpuContext>,
    scene: Arc<scene::Scene>,
    /// Each method keeps its shadow maps between `render` calls (docs/reuse.md).
    reuse: bool,
}

/// V as (H, W) float32 with NaN on background pixels (the engine writes 0 there).
pub fn visibility_array<'py>(
    py: Python<'py>,
    values: &[f32],
    g: &penumbra_lab::render::gbuffer::GBufferCpu,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let v: Vec<f32> = values
        .iter()
        .enumerate()
        .map(|(i, &x)| if g.is_geometry(i) { x } else { f32::NAN })
        .collect();
    numpy_image(py, v, g)
}

/// A (H, W) numpy array that owns `v`'s buffer (no copy).
fn numpy_image<'py>(
    py: Python<'py>,
    v: Vec<f32>,
    g: &penumbra_lab::render::gbuffer::GBufferCpu,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let a = Array2::from_shape_vec((g.height as usize, g.width as usize), v)
        .map_err(|e| crate::PenumbraError::new_err(format!("V: {e}")))?;
    Ok(a.into_pyarray(py))
}

impl Renderer {
    /// Runs `work` on the kept renderer of `spec` (with `params` as `--param` pairs), built (with
    /// one untimed warm-up frame, as `penumbra render` does) on first use. The GIL is released meanwhile.
    fn with_built<T: Send>(
        &self,
        py: Python<'_>,
        spec: &str,
        params: &[(String, String)],
        work: impl FnOnce(&mut Built) -> penumbra_lab::Result<T> + Send,
    ) -> PyResult<T> {
        py.detach(|| -> penumbra_lab::Result<T> {
            let request: Request = (spec.to_string(), params.to_vec());
            let known = self
                .labels
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .get(&request)
                .cloned();
            let mut built = self.built.lock().unwrap_or_else(|e| e.into_inner());
            let key = match known {
                Some(label) => label,
                None => {
                    let method = Method::parse(spec, params)?;
                    method.check_light(&self.scene)?;
                    let key = method.label();
                    if !built.contains_key(&key) {
                        let mut renderer = frame::Renderer::with_reuse(
                            self.ctx.clone(),
                            self.scene.clone(),
                            &method,
                            self.reuse,
                        )?;
                        renderer.frame(TimingMode::Frame)?;
                        built.insert(
                            key.clone(),
                            Built {
                                renderer,
                                method: Arc::new(method),
                            },
                        );
                    }
                    self.labels
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .insert(request, key.clone());
                    key
                }
            };
            work(built.get_mut(&key).expect("built above"))
        })
        .map_err(crate::to_py)
    }

    /// One frame of `method`, certified where `certify` says (V and the record, as `render`).
    fn render_certified<'py>(
        &self,
        py: Python<'py>,
        method: &str,
        params: Option<&Bound<'py, PyDict>>,
        certify: Option<penumbra_lab::certify::Options>,
    ) -> PyResult<(Bound<'py, PyArray2<f32>>, Record)> {
        let (v, pending) = self.with_built(py, method, &crate::pairs(params)?, |b| {
            let mut f = b.renderer.frame(FrameOptions {
                mode: TimingMode::Frame,
                pictures: false,
            })?;
            let certified = match certify {
                Some(options) => {
                    let geometry = f.gbuffer.geometry_count();
                    options
                        .check(geometry)
                        .map_err(|e| penumbra_lab::Error::param(format!("certify: {e}")))?;
                    let ctx: &GpuContext = &self.ctx;
                    let mut certifier =
                        FrameCertifier::new(ctx, &self.scene, options, ProxyKind::SecondOpinion)?;
                    let record = certifier.certify(&f)?;
                    Some(
                        serde_json::to_value(&record)
                            .map_err(|e| penumbra_lab::Error::param(format!("certify: {e}")))?,
                    )
                }
                None => None,
            };
            // One pass writes NaN on the background and sums the record's figures of V (a second
            // pass cost 6 µs at 64² on lavapipe's cores); V then goes to numpy as it is. The record
            // keeps those two figures and none of the G-buffer: a few hundred bytes, not a frame's worth.
            let mut v = std::mem::take(&mut f.visibility);
            let mut sum = VSum::default();
            for (i, x) in v.iter_mut().enumerate() {
                if f.gbuffer.is_geometry(i) {
                    sum.add(*x);
                } else {
                    *x = f32::NAN;
                }
            }
            let figures = sum.figures();
            let g = &mut f.gbuffer;
            (g.position, g.normal, g.shading_normal) = Default::default();
            Ok((
                v,
                Pending {
                    scene: self.scene.clone(),
                    ctx: self.ctx.clone(),
                    method: b.method.clone(),
                    frame: f,
                    v: figures,
                    certify: certified,
                },
            ))
        })?;
        Ok((
            numpy_image(py, v, &pending.frame.gbuffer)?,
            Record::new(pending),
        ))
    }
}

#[pymethods]
impl Renderer {
    /// A renderer for `scene` on `adapter` (a name or part of one; `None`: the CLI's default choice).
    #[new]
    #[pyo3(signature = (scene, adapter=None, reuse=true))]
    fn new(
        py: Python<'_>,
        scene: &Scene,
        adapter: Option<&str>,
        reuse: bool,
    ) -> PyResult<Renderer> {
        let ctx = crate::context::get(py, adapter)?;
        Ok(Renderer {
            built: Mutex::new(HashMap::new()),
            labels: Mutex::new(HashMap::new()),
            ctx,
            scene: scene.inner.clone(),
            reuse,
        })
    }

    /// Renders one frame of `method`.
    ///
    /// Args:
    ///     method: a method spec as `penumbra render --method` takes it (`"pcss"`,
    ///         `"adaptive:preset=balanced"`, `"regular:n=5,layout=centred"`).
    ///     **params: the method's parameters, as `--param key=value` (`p_m=10`, `scope="local"`).
    ///
    /// Returns:
    ///     `(V, record)`: V, the visibility, float32 of shape (height, width), top row first,
    ///     in [0, 1] on geometry and NaN on the background; record, run.json's content.
    ///
    /// Raises:
    ///     PenumbraError: an unknown method or parameter, a value it refuses, a light the method
    ///         cannot take, sizes past the device's limits.
    ///     GpuError: the device failed.
    #[pyo3(signature = (method, **params))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        method: &str,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<(Bound<'py, PyArray2<f32>>, Record)> {
        self.render_certified(py, method, params, None)
    }

    /// Renders one frame of `method` and certifies its error (docs/certify.md).
    ///
    /// Args:
    ///     method: a method spec, as for `render`.
    ///     pixels: how many pixels are drawn and traced exactly by the reference's integrator.
    ///     delta: the bound holds with probability at least 1 − `delta`.
    ///     **params: the method's parameters, as for `render`.
    ///
    /// Returns:
    ///     `(V, record)` as `render`; the record's `certify` holds the one-sided bound on the
    ///     frame's RMSE (`bound`), the drawn pixels' RMSE and the tracing time.
    ///
    /// Raises:
    ///     PenumbraError: as for `render`; `pixels` or `delta` out of range, or a scene the
    ///         exact tracer cannot take.
    ///     GpuError: the device failed.
    #[pyo3(signature = (method, pixels=2048, delta=0.05, **params))]
    fn certify<'py>(
        &self,
        py: Python<'py>,
        method: &str,
        pixels: usize,
        delta: f64,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<(Bound<'py, PyArray2<f32>>, Record)> {
        let options = penumbra_lab::certify::Options {
            pixels,
            delta,
            ..Default::default()
        };
        let frame = self.scene.render.width as usize * self.scene.render.height as usize;
        options
            .check(frame)
            .map_err(|e| crate::PenumbraError::new_err(format!("certify: {e}")))?;
        if let Some(why) = penumbra_lab::certify::truth::unsupported(&self.scene) {
            return Err(crate::PenumbraError::new_err(format!(
                "certify: scene {}: {why}",
                self.scene.origin
            )));
        }
        self.render_certified(py, method, params, Some(options))
    }

    /// The adapter's name.
    #[getter]
    fn adapter(&self) -> &str {
        &self.ctx.summary.name
    }

    /// Methods built so far (their labels); each keeps its pipelines and buffers.
    #[getter]
    fn methods(&self) -> Vec<String> {
        let mut labels: Vec<String> = self
            .built
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .keys()
            .cloned()
            .collect();
        labels.sort();
        labels
    }

    /// Renders one frame with the method's decision pictures on.
    ///
    /// Args:
    ///     method: a method spec, as for `render`.
    ///     **params: the method's parameters, as for `render`.
    ///
    /// Returns:
    ///     The pictures by name, uint8 of shape (height, width, 3): adaptive's `comparison_map`,
    ///     `low_quality` and `light_quadtree`, `samples_per_pixel` with `scope=local`; and
    ///     `error_bound`, float32 (height, width), NaN on the background, where the method
    ///     estimates its error.
    ///
    /// Raises:
    ///     PenumbraError: as for `render`.
    ///     GpuError: the device failed.
    #[pyo3(signature = (method, **params))]
    fn pictures<'py>(
        &self,
        py: Python<'py>,
        method: &str,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let f = self.with_built(py, method, &crate::pairs(params)?, |b| {
            Ok(b.renderer.frame(FrameOptions {
                mode: TimingMode::Frame,
                pictures: true,
            })?)
        })?;
        let out = PyDict::new(py);
        for (name, image) in &f.output.pictures {
            let (w, h) = (image.width(), image.height());
            let a = image
                .as_raw()
                .clone()
                .into_pyarray(py)
                .reshape([h as usize, w as usize, 3])?;
            out.set_item(name.strip_suffix(".png").unwrap_or(name), a)?;
        }
        if let Some(bound) = &f.output.bound {
            out.set_item("error_bound", visibility_array(py, bound, &f.gbuffer)?)?;
        }
        Ok(out)
    }

    /// Wall clock in ms of each of `frames` frames rendered in Rust on the kept renderer, with no
    /// Python in the loop: what `ShadowRenderer::render` costs, for measuring what `render` adds
    /// (scripts/python-overhead.py).
    #[pyo3(signature = (method, frames, **params))]
    fn _rust_frame_times(
        &self,
        py: Python<'_>,
        method: &str,
        frames: u32,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Vec<f64>> {
        self.with_built(py, method, &crate::pairs(params)?, |b| {
            (0..frames)
                .map(|_| {
                    let start = std::time::Instant::now();
                    b.renderer.frame(FrameOptions {
                        mode: TimingMode::Frame,
                        pictures: false,
                    })?;
                    Ok(start.elapsed().as_secs_f64() * 1e3)
                })
                .collect()
        })
    }
}
