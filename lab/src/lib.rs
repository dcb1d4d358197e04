//! The lab over the penumbra engine: the CPU ground truth, metrics, run records, studies,
//! charts and reports, the asset fetch and the `penumbra` binary's inputs.
//!
//! The engine's modules are re-exported under their own names, so lab code reads
//! `crate::gpu`, `crate::scene`, … as before; the engine cannot name anything here.

pub use penumbra::{api, certify, frame, gpu, methods, render, scene, stages};
pub use penumbra::{required_limits, version, LONG_VERSION, Camera, Mesh, RectLight, SceneBuilder, ShadowRenderer, ShadowScene, Shadows, Visibility, OPTIONAL_FEATURES};

pub(crate) mod error;
pub mod progress;
pub mod assets;
pub mod reference;
pub mod metrics;
pub mod record;
pub mod report;
pub mod studies;
pub mod inputs;
pub mod interrupt;
pub mod panic_log;

pub use error::{cli_words, Error, Result};

/// Registers the lab with the engine: progress bars on the terminal and the asset layer
/// (`cache:` paths, the registry mesh formats). The binary calls it first; so may any program
/// or test that wants the same scenes to load.
pub fn install() {
    progress::install();
    assets::install();
}
