//! `penumbra._penumbra`: the engine and the lab from Python (the package python/penumbra/ wraps it).
//!
//! Every call that touches the GPU or traces the reference releases the GIL (`Python::detach`), so
//! other Python threads run meanwhile. Bad input becomes `penumbra.PenumbraError` (a `ValueError`)
//! carrying the one-line message `penumbra` prints after `error:`, a render setting named as the
//! keyword argument it came from (`cull='sideways'`, where the command line says `--set`); a failing
//! device (lost, no adapter, a kernel that does not validate) becomes `penumbra.GpuError`, a
//! `RuntimeError`. The signatures are in `penumbra/_penumbra.pyi`.

mod analysis;
mod context;
mod progress;
mod record;
mod renderer;
mod scene;
mod truth;

use pyo3::prelude::*;
use pyo3::types::{PyAny, PyDict};

pyo3::create_exception!(penumbra, PenumbraError, pyo3::exceptions::PyValueError, "Bad input: a scene, setting, method, parameter or file that penumbra refuses; the message is the command line's `error:` line.");
pyo3::create_exception!(penumbra, GpuError, pyo3::exceptions::PyRuntimeError, "The GPU failed: no adapter matches, the device was lost or ran out of memory, a kernel did not validate, a counter overflowed.");

/// The lab's error as the Python exception of its kind, with the CLI's message.
pub(crate) fn to_py(e: penumbra_lab::Error) -> PyErr {
    match e {
        penumbra_lab::Error::Engine(e) => engine(e),
        e => PenumbraError::new_err(e.to_string()),
    }
}

/// The engine's error as the Python exception of its kind: the device's failures a `GpuError`,
/// the rest bad input; a render setting named as its keyword argument.
pub(crate) fn engine(e: penumbra::Error) -> PyErr {
    use penumbra::Error as Engine;
    match e {
        Engine::Gpu(_) | Engine::Kernel { .. } | Engine::NoAdapter(_) | Engine::Overflow(_) => {
            GpuError::new_err(e.to_string())
        }
        Engine::Setting {
            origin,
            key,
            value,
            why,
        } => {
            let origin = origin.map(|o| format!("{o}: ")).unwrap_or_default();
            let value = value
                .map(|v| format!("={}", python_literal(&v)))
                .unwrap_or_default();
            PenumbraError::new_err(format!("{origin}{key}{value}: {why}"))
        }
        Engine::Input { input, value, why } => PenumbraError::new_err(format!(
            "{}={}: {why}",
            input.name(),
            python_literal(&value)
        )),
        e => PenumbraError::new_err(e.to_string()),
    }
}

/// A setting's value text as the Python literal that gives it: numbers and booleans as they are
/// written in Python, anything else quoted (`'sideways'`).
fn python_literal(text: &str) -> String {
    match text {
        "true" => "True".into(),
        "false" => "False".into(),
        t if t.parse::<f64>().is_ok() => t.into(),
        t => format!("'{}'", t.replace('\\', "\\\\").replace('\'', "\\'")),
    }
}

/// `key=value` pairs from Python keyword arguments, spelled as on the command line (`True` → `true`).
pub(crate) fn pairs(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, String)>> {
    let Some(kwargs) = kwargs else {
        return Ok(Vec::new());
    };
    kwargs
        .iter()
        .map(|(k, v)| Ok((k.extract::<String>()?, value_text(&v)?)))
        .collect()
}

fn value_text(v: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(b) = v.extract::<bool>() {
        return Ok(b.to_string());
    }
    Ok(v.str()?.to_string())
}

/// A JSON value as the Python object `json.loads` would give, built directly (a run record
/// costs a few microseconds this way; through text and `json.loads`, several times that).
pub(crate) fn json_to_py<'py>(
    py: Python<'py>,
    v: &serde_json::Value,
) -> PyResult<Bound<'py, PyAny>> {
    use pyo3::types::PyList;
    use serde_json::Value;
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => match (n.as_i64(), n.as_u64()) {
            (Some(i), _) => i.into_pyobject(py)?.into_any(),
            (None, Some(u)) => u.into_pyobject(py)?.into_any(),
            _ => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(items) => PyList::new(
            py,
            items
                .iter()
                .map(|x| json_to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?,
        )?
        .into_any(),
        Value::Object(map) => {
            let d = PyDict::new(py);
            for (k, x) in map {
                d.set_item(k, json_to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
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
    m.add_class::<record::Record>()?;
    m.add_class::<truth::Reference>()?;
    m.add_function(wrap_pyfunction!(truth::reference, m)?)?;
    m.add_function(wrap_pyfunction!(truth::metrics, m)?)?;
    m.add_function(wrap_pyfunction!(truth::compare_methods, m)?)?;
    m.add_function(wrap_pyfunction!(truth::read_exr, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::analysis_constants, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::method_params, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::auto_predicted_at, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::regions_half_octave, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::regions_density_floor, m)?)?;
    Ok(())
}
