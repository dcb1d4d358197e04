//! Compute stages, one WGSL file each; the stage name (one entry of the stage table,
//! `gpu::stages`) is the file, the pipeline label, the CPU twin (`stages::twin`) and the timing key.

pub mod adaptive_buffers;
pub(crate) mod blur;
pub mod cascades;
pub mod compact;
pub mod cull;
pub(crate) mod env_count;
pub(crate) mod env_shadowmaps;
pub(crate) mod env_split;
pub(crate) mod env_trace;
pub(crate) mod env_vertex_interp;
pub mod estimate;
pub mod footprint;
pub(crate) mod frame_gpu;
pub mod hybrid_build;
pub mod hybrid_pool;
pub(crate) mod kernel;
pub(crate) mod moments;
pub mod neighbourhood;
pub(crate) mod pcf;
pub(crate) mod pcss;
pub mod probe;
pub mod quad_count;
pub mod raster;
pub mod raster_auto;
pub mod raster_compute;
pub mod raster_timing;
pub(crate) mod reconstruct;
pub mod regions;
pub mod regions_rules;
pub mod reproject_count;
pub mod shade;
pub mod shadow_test;
pub(crate) mod ssao;
pub mod subdivide;
pub mod truth_trace;
pub mod twin;
pub mod weights;

pub use frame_gpu::{FrameGpu, FrameParts};
pub use kernel::{ComputeKernel, Dispatch};
// Workgroup sizes live in the stage table (gpu::stages), which tests/kernels.rs checks with naga.
pub use crate::gpu::stages::{LINE_WORKGROUP, PIXEL_WORKGROUP};

/// Workgroups needed to cover `n` items with groups of `size` (the one place dispatch sizes are computed).
pub fn groups(n: u32, size: u32) -> u32 {
    n.div_ceil(size)
}
