//! `penumbra.Record`: a frame's run record (run.json's content), built when it is first read.
//!
//! Building the record and its dict costs about 35 µs, 2.5 to 4% of a warm 64² hard frame on
//! lavapipe (results/python-overhead/), and a loop that renders for V alone never reads it. So
//! `render` keeps what the record is built from and builds the dict on the first read; V and the
//! G-buffer are not kept (V went to numpy, the record needs only its `VFigures`).

use penumbra_lab::frame::FrameResult;
use penumbra_lab::gpu::GpuContext;
use penumbra_lab::methods::Method;
use penumbra_lab::record::run_files::{self, VFigures};
use penumbra_lab::scene::Scene;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyIterator, PyList};
use std::sync::{Arc, Mutex, OnceLock};

/// What `run_files::run_record_of` reads, until the record is first read.
pub struct Pending {
    pub scene: Arc<Scene>,
    pub ctx: Arc<GpuContext>,
    pub method: Arc<Method>,
    /// The frame with its V and G-buffer moved out.
    pub frame: FrameResult,
    pub v: VFigures,
    /// `Renderer.certify`: the frame's certificate, run.json's `certify`.
    pub certify: Option<serde_json::Value>,
}

/// The run record of one frame: run.json's content, read as a dict is.
#[pyclass(module = "penumbra", frozen, mapping)]
pub struct Record {
    pending: Mutex<Option<Pending>>,
    value: OnceLock<serde_json::Value>,
    dict: OnceLock<Py<PyDict>>,
}

impl Record {
    pub fn new(pending: Pending) -> Record {
        Record {
            pending: Mutex::new(Some(pending)),
            value: OnceLock::new(),
            dict: OnceLock::new(),
        }
    }

    fn value(&self) -> &serde_json::Value {
        self.value.get_or_init(|| {
            let p = self
                .pending
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .take()
                .expect("a record is built once");
            let mut record = run_files::run_record_of(
                &p.scene,
                &p.method,
                &p.frame,
                p.v,
                &p.ctx.summary,
                p.ctx.timestamps_trusted,
            );
            if let Some(c) = p.certify {
                record["certify"] = c;
            }
            record
        })
    }

    /// The dict every read goes through, built on the first.
    fn dict<'py>(&self, py: Python<'py>) -> PyResult<&Bound<'py, PyDict>> {
        if self.dict.get().is_none() {
            let d = crate::json_to_py(py, self.value())?
                .cast_into::<PyDict>()?
                .unbind();
            // Another thread that built it meanwhile wins; both are the same record.
            let _ = self.dict.set(d);
        }
        Ok(self.dict.get().expect("set above").bind(py))
    }
}

#[pymethods]
impl Record {
    fn __getitem__<'py>(
        &self,
        py: Python<'py>,
        key: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.dict(py)?.as_any().get_item(key)
    }

    fn __contains__(&self, py: Python<'_>, key: &Bound<'_, PyAny>) -> PyResult<bool> {
        self.dict(py)?.contains(key)
    }

    fn __len__(&self, py: Python<'_>) -> PyResult<usize> {
        Ok(self.dict(py)?.len())
    }

    fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyIterator>> {
        self.dict(py)?.as_any().try_iter()
    }

    fn __eq__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<bool> {
        let other = match other.cast::<Record>() {
            Ok(r) => r.get().dict(py)?.clone().into_any(),
            Err(_) => other.clone(),
        };
        self.dict(py)?.as_any().eq(other)
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        Ok(format!("Record({})", self.dict(py)?.repr()?))
    }

    fn keys<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        Ok(self.dict(py)?.keys())
    }

    fn values<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        Ok(self.dict(py)?.values())
    }

    fn items<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        Ok(self.dict(py)?.items())
    }

    #[pyo3(signature = (key, default=None))]
    fn get<'py>(
        &self,
        py: Python<'py>,
        key: &Bound<'py, PyAny>,
        default: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        Ok(match self.dict(py)?.get_item(key)? {
            Some(v) => v,
            None => default.unwrap_or_else(|| py.None().into_bound(py)),
        })
    }

    /// The record as a new plain dict, its own copy down to the nested values.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::json_to_py(py, self.value())
    }
}
