//! Compute stages, one WGSL file each; the stage name (one entry of the stage table,
//! `gpu::stages`) is the file, the pipeline label, the CPU twin (`stages::twin`) and the timing key.

pub(crate) mod adaptive_buffers;
pub(crate) mod blur;
pub(crate) mod cascades;
pub(crate) mod compact;
pub(crate) mod cull;
pub(crate) mod env_count;
pub(crate) mod env_shadowmaps;
pub(crate) mod env_split;
pub(crate) mod env_trace;
pub(crate) mod env_vertex_interp;
pub(crate) mod estimate;
pub(crate) mod footprint;
pub(crate) mod frame_gpu;
pub(crate) mod hybrid_build;
pub(crate) mod hybrid_pool;
pub(crate) mod kernel;
pub(crate) mod moments;
pub(crate) mod neighbourhood;
pub(crate) mod pcf;
pub(crate) mod pcss;
pub(crate) mod probe;
pub(crate) mod quad_count;
pub(crate) mod raster;
pub(crate) mod raster_auto;
pub(crate) mod raster_compute;
pub(crate) mod raster_timing;
pub(crate) mod reconstruct;
pub(crate) mod regions;
pub(crate) mod regions_rules;
pub(crate) mod reproject_count;
pub(crate) mod shade;
pub(crate) mod shadow_test;
pub(crate) mod ssao;
pub(crate) mod subdivide;
pub(crate) mod truth_trace;
// The CPU twins check the kernels: built for the tests (and the `twins` feature they enable), never
// for a product build, so no product code can read one.
#[cfg(any(test, feature = "twins"))]
pub mod twin;
pub(crate) mod weights;

pub(crate) use frame_gpu::{FrameGpu, FrameParts};
pub(crate) use kernel::{ComputeKernel, Dispatch};
// Workgroup sizes live in the stage table (gpu::stages), which tests/kernels.rs checks with naga.
pub(crate) use crate::gpu::stages::{LINE_WORKGROUP, PIXEL_WORKGROUP};

/// Workgroups needed to cover `n` items with groups of `size` (the one place dispatch sizes are computed).
pub(crate) fn groups(n: u32, size: u32) -> u32 {
    n.div_ceil(size)
}
