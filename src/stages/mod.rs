//! Compute stages, one WGSL file each; the stage name is the file, the pipeline label, the CPU twin
//! (`compute::twin`) and the timing key.

pub mod blur;
pub mod compact;
pub mod cull;
pub mod env_count;
pub mod env_shadowmaps;
pub mod env_split;
pub mod env_trace;
pub mod env_vertex_interp;
pub mod frame_gpu;
pub mod hybrid_build;
pub mod kernel;
pub mod moments;
pub mod neighbourhood;
pub mod pcf;
pub mod pcss;
pub mod probe;
pub mod quad_count;
pub mod reconstruct;
pub mod reproject_count;
pub mod shade;
pub mod shadow_test;
pub mod ssao;
pub mod subdivide;
pub mod weights;
pub mod twin;

pub use frame_gpu::FrameGpu;
pub use kernel::{ComputeKernel, Dispatch};

/// Workgroups needed to cover `n` items with groups of `size` (the one place dispatch sizes are computed).
pub fn groups(n: u32, size: u32) -> u32 {
    n.div_ceil(size)
}

/// 2D pixel kernels.
pub const PIXEL_WORKGROUP: [u32; 3] = [8, 8, 1];
/// 1D kernels over words, items or quads.
pub const LINE_WORKGROUP: [u32; 3] = [64, 1, 1];

/// Workgroup sizes the Rust side dispatches with; a test asserts naga reads the same from each kernel.
pub const WORKGROUP_SIZES: &[(&str, &str, [u32; 3])] = &[
    ("shade", "block16", PIXEL_WORKGROUP),
    ("shade", "block8", PIXEL_WORKGROUP),
    ("shade", "block4", PIXEL_WORKGROUP),
    ("shade", "block2", PIXEL_WORKGROUP),
    ("shade", "block1", PIXEL_WORKGROUP),
    ("shade", "from_masks", PIXEL_WORKGROUP),
    ("shadow_test", "fill_blocks", [1, 1, 1]),
    ("shadow_test", "block16", PIXEL_WORKGROUP),
    ("shadow_test", "block8", PIXEL_WORKGROUP),
    ("shadow_test", "block4", PIXEL_WORKGROUP),
    ("shadow_test", "block2", PIXEL_WORKGROUP),
    ("shadow_test", "block1", PIXEL_WORKGROUP),
    ("shadow_test", "list", LINE_WORKGROUP),
    ("shadow_test", "probes", LINE_WORKGROUP),
    ("reproject_count", "main", LINE_WORKGROUP),
    ("reproject_count", "list", LINE_WORKGROUP),
    ("reproject_count", "last", LINE_WORKGROUP),
    ("reproject_count", "begin", [1, 1, 1]),
    ("neighbourhood", "main", LINE_WORKGROUP),
    ("neighbourhood", "list", LINE_WORKGROUP),
    ("quad_count", "main", LINE_WORKGROUP),
    ("subdivide", "main", LINE_WORKGROUP),
    ("compact", "main", LINE_WORKGROUP),
    ("compact", "main_rects", LINE_WORKGROUP),
    ("compact", "seed", PIXEL_WORKGROUP),
    ("compact", "resolve", PIXEL_WORKGROUP),
    ("pcf", "main", PIXEL_WORKGROUP),
    ("pcss", "main", PIXEL_WORKGROUP),
    ("moments", "main", PIXEL_WORKGROUP),
    ("blur", "horizontal", PIXEL_WORKGROUP),
    ("blur", "vertical", PIXEL_WORKGROUP),
    ("reconstruct", "main", PIXEL_WORKGROUP),
    ("probe", "main", LINE_WORKGROUP),
    ("probe", "begin", [1, 1, 1]),
    ("env_trace", "main", PIXEL_WORKGROUP),
    ("env_trace", "vertex", LINE_WORKGROUP),
    ("env_vertex_interp", "main", PIXEL_WORKGROUP),
    ("env_count", "main", LINE_WORKGROUP),
    ("env_split", "main", LINE_WORKGROUP),
    ("env_shadowmaps", "main", PIXEL_WORKGROUP),
    ("ssao", "main", PIXEL_WORKGROUP),
    ("cull", "main", LINE_WORKGROUP),
    ("cull", "begin", [1, 1, 1]),
    ("cull", "triangles", [cull::CULL_RUN, 1, 1]),
    ("weights", "leaves_of_level", LINE_WORKGROUP),
    ("weights", "main", [1, 1, 1]),
    ("hybrid_build", "classify", PIXEL_WORKGROUP),
    ("hybrid_build", "scan_rows", LINE_WORKGROUP),
    ("hybrid_build", "scan_total", [1, 1, 1]),
    ("hybrid_build", "emit", PIXEL_WORKGROUP),
];
