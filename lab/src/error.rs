//! The lab's error: the engine's, or one of the lab's own (reference, metrics, charts, report,
//! assets); the binary wraps it in `anyhow`.

use std::path::Path;

pub use penumbra::toml_position;

pub type Result<T, E = Error> = std::result::Result<T, E>;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The engine's error (scene, mesh, GPU, parameters, files, …), in the command line's words.
    #[error("{}", cli_words(.0))]
    Engine(#[from] penumbra::Error),
    /// The CPU ground truth failed (degenerate light, cache file unreadable).
    #[error("reference: {0}")]
    Reference(#[from] crate::reference::ReferenceError),
    /// Metrics could not be computed (sizes disagree, no geometry).
    #[error("metrics: {0}")]
    Metrics(#[from] crate::metrics::MetricsError),
    /// A chart could not be drawn or rasterised.
    #[error("chart: {0}")]
    Chart(#[from] crate::report::charts::ChartError),
    /// The report could not be written.
    #[error("report: {0}")]
    Report(#[from] crate::report::ReportError),
    /// Fetching or loading a registry asset (its message names the file and the line or element).
    #[error(transparent)]
    Asset(#[from] crate::assets::AssetError),
}

/// The engine's error as the command line says it: a render setting by its flag, `--set key=value`,
/// an input by its flag (`--scene`, `--backend`), and how to fetch an asset or raise a cap.
/// (Python words the same error by its keyword argument.)
pub fn cli_words(e: &penumbra::Error) -> String {
    match e {
        penumbra::Error::Setting {
            origin,
            key,
            value,
            why,
        } => {
            let origin = origin
                .as_ref()
                .map(|o| format!("{o}: "))
                .unwrap_or_default();
            let value = value.as_ref().map(|v| format!("={v}")).unwrap_or_default();
            format!("{origin}--set {key}{value}: {why}")
        }
        penumbra::Error::Input { input, value, why } => {
            format!("--{input} {}: {why}", penumbra::show_value(value))
        }
        penumbra::Error::ParamTwice {
            spec,
            key,
            first,
            again,
        } => format!("method `{spec}`: `{key}` is given twice ({first}, and {again} with --param)"),
        penumbra::Error::MissingAsset {
            file,
            missing,
            group,
        } => format!(
            "{file}: not in the asset cache ({missing} is missing): run `penumbra assets fetch --group {group}` (cache folder: --cache or $PENUMBRA_CACHE)"
        ),
        penumbra::Error::MeshCap { message, .. } => {
            format!("{message} (raise it with --max-mesh-mib N)")
        }
        e => e.to_string(),
    }
}

impl Error {
    pub fn scene(origin: impl Into<String>, message: impl Into<String>) -> Self {
        penumbra::Error::scene(origin, message).into()
    }
    pub fn mesh(origin: impl Into<String>, message: impl Into<String>) -> Self {
        penumbra::Error::mesh(origin, message).into()
    }
    pub fn io(path: &Path, err: impl std::fmt::Display) -> Self {
        penumbra::Error::io(path, err).into()
    }
    /// Reading or writing `path` (a file, or what stands for one: `<APNG encoder>`) failed.
    pub fn io_text(path: String, message: String) -> Self {
        penumbra::Error::Io { path, message }.into()
    }
    /// A GPU operation failed (the engine's `Gpu`).
    pub fn gpu(message: String) -> Self {
        penumbra::Error::Gpu(message).into()
    }
    /// A size exceeds what the device or the budget allows (the engine's `Limit`).
    pub fn limit(message: String) -> Self {
        penumbra::Error::Limit(message).into()
    }
    /// A method name or parameter is wrong (the engine's `Param`).
    pub fn param(message: String) -> Self {
        penumbra::Error::Param(message).into()
    }
}
