//! The lab over the penumbra engine: the CPU ground truth, metrics, run records, studies,
//! charts and reports, the asset fetch and the `penumbra` binary's inputs.
//!
//! The engine's research façade (`penumbra::research`) is re-exported under its modules' names,
//! so lab code reads `crate::gpu`, `crate::scene`, … as before; the engine cannot name anything
//! here.

pub use penumbra::api;
pub use penumbra::research::{certify, frame, gpu, methods, render, scene, stages};
pub use penumbra::{
    required_limits, version, Camera, Mesh, RectLight, SceneBuilder, ShadowRenderer, ShadowScene,
    Shadows, Visibility, LONG_VERSION, OPTIONAL_FEATURES,
};

pub mod assets;
pub(crate) mod error;
pub mod inputs;
pub mod interrupt;
pub mod metrics;
pub mod panic_log;
pub mod progress;
pub mod record;
pub mod reference;
pub mod report;
pub mod studies;

pub use error::{cli_words, Error, Result};

/// Registers the lab with the engine: progress bars on the terminal and the asset layer
/// (`cache:` paths, the registry mesh formats). The binary calls it first; so may any program
/// or test that wants the same scenes to load.
pub fn install() {
    progress::install();
    assets::install();
}
