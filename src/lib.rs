//! Penumbra: soft shadows from rectangular area lights on a compute-centric wgpu pipeline.
//!
//! **To embed it** in a program with its own wgpu device, start at the [`api`] module: its types
//! are re-exported here ([`Shadows`], [`SceneBuilder`], [`ShadowRenderer`], …). The other modules
//! are the pipeline itself; the `penumbra` binary and its studies live in the lab crate (lab/).
//!
//! Data flows one way and the modules read in that order:
//! scene ─► GPU upload ─► G-buffer ─► light samples ─► shadow-map raster
//! ─► compute (reproject_count ─► neighbourhood ─► quad_count ─► subdivide) ─► shade ─► run record.

pub mod api;
pub mod certify;
pub(crate) mod error;
pub mod frame;
pub mod gpu;
pub mod methods;
pub mod progress;
pub mod render;
pub mod scene;
pub mod stages;

pub use api::{
    required_limits, Camera, Mesh, RectLight, SceneBuilder, ShadowRenderer, ShadowScene, Shadows,
    Visibility, OPTIONAL_FEATURES,
};
pub use error::{show_value, toml_position, Error, Input, Result};

/// `0.1.0 (git <hash>)`: the version line of the `penumbra` binary.
pub const LONG_VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (git ",
    env!("PENUMBRA_GIT_HASH"),
    ")"
);

/// The crate version and the git hash it was built from, as every record carries them.
pub fn version() -> serde_json::Value {
    serde_json::json!({ "crate": env!("CARGO_PKG_VERSION"), "git": env!("PENUMBRA_GIT_HASH") })
}
