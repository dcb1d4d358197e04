//! `penumbra._penumbra`: the engine and the lab from Python (the package python/penumbra/ wraps it).
//!
//! Every call that touches the GPU or traces the reference releases the GIL (`Python::detach`), so
//! other Python threads run meanwhile. Errors become `penumbra.PenumbraError` (a `ValueError`)
//! carrying the same one-line message `penumbra` prints after `error:`; failures of the device
//! itself become `penumbra.GpuError`, its subclass.

mod context;
mod renderer;
mod scene;
mod truth;

use pyo3::prelude::*;
use pyo3::types::{PyAny, PyDict};

pyo3::create_exception!(penumbra, PenumbraError, pyo3::exceptions::PyValueError, "Bad input or a failed run; the message is the command line's `error:` line.");
pyo3::create_exception!(penumbra, GpuError, PenumbraError, "The device failed (lost, out of memory, a kernel that does not validate).");

/// The lab's error as the Python exception of its kind, with the CLI's message.
pub(crate) fn to_py(e: penumbra_lab::Error) -> PyErr {
    use penumbra::Error as Engine;
    let message = e.to_string();
    match e {
        penumbra_lab::Error::Engine(Engine::Gpu(_) | Engine::Kernel { .. } | Engine::NoAdapter(_) | Engine::Overflow(_)) => GpuError::new_err(message),
        _ => PenumbraError::new_err(message),
    }
}

pub(crate) fn engine(e: penumbra::Error) -> PyErr {
    to_py(e.into())
}

/// `key=value` pairs from Python keyword arguments, spelled as on the command line (`True` → `true`).
pub(crate) fn pairs(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, String)>> {
    let Some(kwargs) = kwargs else { return Ok(Vec::new()) };
    kwargs.iter().map(|(k, v)| Ok((k.extract::<String>()?, value_text(&v)?))).collect()
}

fn value_text(v: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(b) = v.extract::<bool>() {
        return Ok(b.to_string());
    }
    Ok(v.str()?.to_string())
}

/// A JSON value as the Python object `json.loads` would give.
pub(crate) fn json_to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(v).map_err(|e| PenumbraError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}

#[pymodule]
fn _penumbra(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // The same scenes load as on the command line (`cache:` meshes, registry formats); progress
    // bars draw only on a terminal.
    penumbra_lab::install();
    m.add("PenumbraError", m.py().get_type::<PenumbraError>())?;
    m.add("GpuError", m.py().get_type::<GpuError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<renderer::Renderer>()?;
    m.add_class::<truth::Reference>()?;
    m.add_function(wrap_pyfunction!(truth::reference, m)?)?;
    m.add_function(wrap_pyfunction!(truth::metrics, m)?)?;
    m.add_function(wrap_pyfunction!(truth::compare_methods, m)?)?;
    m.add_function(wrap_pyfunction!(truth::read_exr, m)?)?;
    Ok(())
}
