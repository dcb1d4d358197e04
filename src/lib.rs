//! Penumbra: soft shadows from rectangular area lights on a compute-centric wgpu pipeline.
//!
//! **To embed it** in a program with its own wgpu device, start at the [`api`] module: its types
//! are re-exported here ([`Shadows`], [`SceneBuilder`], [`ShadowRenderer`], …). The lab crate
//! (lab/: the `penumbra` binary, its studies), the Python binding and the tests also reach the
//! pipeline's insides through one named door, [`research`]; every other module is private to the
//! crate, so the public surface is the API plus that façade (tests/layers.rs counts it).
//!
//! Data flows one way and the modules read in that order:
//! scene ─► GPU upload ─► G-buffer ─► light samples ─► shadow-map raster
//! ─► compute (reproject_count ─► neighbourhood ─► quad_count ─► subdivide) ─► shade ─► run record.

// A `pub` item that outside code cannot reach is written `pub(crate)`: then every `pub` in src/ is
// part of the public surface, and tests/layers.rs counts that surface by counting `pub`.
#![warn(unreachable_pub)]

pub mod api;
pub(crate) mod certify;
pub(crate) mod error;
pub(crate) mod frame;
pub(crate) mod gpu;
pub(crate) mod methods;
pub(crate) mod progress;
pub(crate) mod render;
pub mod research;
pub(crate) mod scene;
pub(crate) mod stages;

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
