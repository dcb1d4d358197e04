//! One GPU context per adapter request for the whole process: creating a device costs tens of
//! milliseconds and compiled pipelines are cached per device, so renderers, references and
//! compares share it.

use penumbra_lab::gpu::{AdapterRequest, BackendChoice, GpuContext};
use pyo3::prelude::*;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// The context for `adapter` (a name or part of one, as `penumbra --adapter` takes it; `None`:
/// `WGPU_ADAPTER_NAME`, else the default choice). `WGPU_BACKEND` picks the backend, as for the CLI.
pub fn get(py: Python<'_>, adapter: Option<&str>) -> PyResult<Arc<GpuContext>> {
    // One context per (backend, adapter) request.
    type Contexts = Mutex<HashMap<(String, Option<String>), Arc<GpuContext>>>;
    static CONTEXTS: OnceLock<Contexts> = OnceLock::new();
    let (backend, source) = match std::env::var("WGPU_BACKEND") {
        Ok(b) => (b, "WGPU_BACKEND"),
        Err(_) => ("auto".to_string(), "backend"),
    };
    // The engine names the backend in its own words; say it as the user gave it.
    let choice = BackendChoice::parse(&backend).map_err(|e| match e {
        penumbra::Error::Input { value, why, .. } => crate::PenumbraError::new_err(format!(
            "{source} {}: {why}",
            penumbra::show_value(&value)
        )),
        e => crate::PenumbraError::new_err(format!("{source}: {e}")),
    })?;
    let name = adapter
        .map(str::to_string)
        .or_else(|| std::env::var("WGPU_ADAPTER_NAME").ok())
        .filter(|n| !n.is_empty());
    let key = (backend, name.clone());
    let contexts = CONTEXTS.get_or_init(Default::default);
    if let Some(ctx) = contexts.lock().unwrap().get(&key) {
        return Ok(ctx.clone());
    }
    let request = AdapterRequest {
        backend: choice,
        name,
        source: Some(source.to_string()),
    };
    let ctx = Arc::new(
        py.detach(|| GpuContext::with_request(&request))
            .map_err(crate::engine)?,
    );
    contexts.lock().unwrap().insert(key, ctx.clone());
    Ok(ctx)
}
