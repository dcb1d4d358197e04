//! Penumbra: soft shadows from rectangular area lights on a compute-centric wgpu pipeline.
//!
//! Data flows one way and the modules read in that order:
//! scene ─► GPU upload ─► G-buffer ─► light samples ─► shadow-map raster
//! ─► compute (reproject_count ─► neighbourhood ─► quad_count ─► subdivide) ─► shade ─► run record.

pub mod error;
pub mod gpu;
pub mod kernels;
pub mod layout;
pub mod light;
pub mod scene;
pub mod render;
pub mod compute;
pub mod methods;
pub mod frame;
pub mod output;
pub mod output_set;
pub mod timing;
pub mod progress;
pub mod reference;
pub mod metrics;
pub mod charts;
pub mod record;
pub mod report;
pub mod ground_truth;
pub mod compare;
pub mod shard;
pub mod check;
pub mod framing;
pub mod hybrid_study;
pub mod assets;
pub mod bench;
pub mod inputs;
pub mod sequence;
pub mod failures;

pub use error::{Error, Result};
