//! Penumbra: soft shadows from rectangular area lights on a compute-centric wgpu pipeline.
//!
//! Data flows one way and the modules read in that order:
//! scene ─► GPU upload ─► G-buffer ─► light samples ─► shadow-map raster
//! ─► compute (reproject_count ─► neighbourhood ─► quad_count ─► subdivide) ─► shade ─► run record.

pub mod error;
pub mod progress;
pub mod gpu;
pub mod scene;
pub mod render;
pub mod stages;
pub mod methods;
pub mod frame;
pub mod reference;
pub mod metrics;
pub mod record;
pub mod report;
pub mod studies;
pub mod inputs;

pub use error::{Error, Result};
