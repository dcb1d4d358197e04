//! One error type for the library; the binary wraps it in `anyhow`.

use std::path::Path;

pub type Result<T, E = Error> = std::result::Result<T, E>;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scene file (or built-in scene) is malformed; `origin` names the file.
    #[error("{origin}: {message}")]
    Scene { origin: String, message: String },
    /// A mesh file is missing, unreadable or malformed.
    #[error("{origin}: {message}")]
    Mesh { origin: String, message: String },
    /// No usable GPU adapter.
    #[error("{0}")]
    NoAdapter(String),
    /// A requested size exceeds what the device or the budget allows and cannot be split.
    #[error("{0}")]
    Limit(String),
    /// A kernel failed to compile or validate.
    #[error("kernel `{name}`: {message}")]
    Kernel { name: String, message: String },
    /// A GPU operation failed (device lost, validation, mapping).
    #[error("gpu: {0}")]
    Gpu(String),
    /// A method name or parameter is wrong.
    #[error("{0}")]
    Param(String),
    /// A counter overflowed its buffer on the GPU.
    #[error("overflow: {0}")]
    Overflow(String),
    /// Reading or writing a file failed.
    #[error("{path}: {message}")]
    Io { path: String, message: String },
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
    Asset(#[from] crate::scene::assets::AssetError),
}

impl Error {
    pub fn scene(origin: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Scene { origin: origin.into(), message: message.into() }
    }
    pub fn mesh(origin: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Mesh { origin: origin.into(), message: message.into() }
    }
    pub fn io(path: &Path, err: impl std::fmt::Display) -> Self {
        Error::Io { path: path.display().to_string(), message: err.to_string() }
    }
}

/// `line L, column C` of a TOML error in `text` (1-based), when the error has a position.
pub fn toml_position(text: &str, e: &toml::de::Error) -> Option<(usize, usize)> {
    let start = e.span()?.start.min(text.len());
    let before = &text[..start];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    Some((before.matches('\n').count() + 1, before[line_start..].chars().count() + 1))
}
