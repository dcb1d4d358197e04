//! Headless GPU access: device selection, pipelines, buffers and read-backs.

pub(crate) mod adapter;
pub mod allocation;
pub(crate) mod context;
pub mod kernels;
pub mod pipeline;
pub mod readback;
pub mod size_plan;
pub mod stages;
pub mod structs;
pub mod timing;

pub use adapter::{AdapterRequest, BackendChoice};
pub use context::{AdapterSummary, GpuContext};
pub use stages::Stage;
