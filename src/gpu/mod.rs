//! Headless GPU access: device selection, pipelines, buffers and read-backs.

pub mod context;
pub mod pipeline;
pub mod readback;

pub use context::{AdapterSummary, GpuContext};
