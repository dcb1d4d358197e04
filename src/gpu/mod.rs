//! Headless GPU access: device selection, pipelines, buffers and read-backs.

pub(crate) mod adapter;
pub(crate) mod allocation;
pub(crate) mod context;
pub(crate) mod kernels;
pub(crate) mod pipeline;
pub(crate) mod readback;
pub(crate) mod size_plan;
pub(crate) mod stages;
pub(crate) mod structs;
pub(crate) mod timing;

pub use adapter::{AdapterRequest, BackendChoice};
pub use context::{AdapterSummary, GpuContext};
pub use stages::Stage;
