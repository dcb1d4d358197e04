//! Headless GPU access: device selection, pipelines, buffers and read-backs.

pub mod adapter;
pub mod context;
pub mod kernels;
pub mod pipeline;
pub mod readback;
pub mod structs;
pub mod timing;

pub use adapter::{AdapterRequest, BackendChoice};
pub use context::{AdapterSummary, GpuContext};
