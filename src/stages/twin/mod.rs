//! CPU twins of the compute kernels, written loop for loop like the WGSL with the same inputs.
//! Tests compare them with the GPU: exactly for every count, flag, quad and sample.

pub mod blur;
pub mod cascades;
pub mod compact;
pub mod cull;
pub mod env_count;
pub mod env_shadowmaps;
pub mod env_split;
pub mod env_trace;
pub mod env_vertex_interp;
pub mod estimate;
pub mod footprint;
pub mod hybrid_build;
pub mod local;
pub mod moments;
pub mod neighbourhood;
pub mod pcf;
pub mod pcss;
pub mod probe;
pub mod quad_count;
pub mod raster_compute;
pub mod reconstruct;
pub mod regions;
pub mod reproject_count;
pub mod shade;
pub mod shadow;
pub mod shadow_test;
pub mod ssao;
pub mod subdivide;
pub mod synthetic;

/// Lattice index of corner c (0..3: (0,0), (1,0), (0,1), (1,1)) of a quad, as `quad_corner` in WGSL.
pub fn quad_corner(q: &crate::gpu::structs::GpuQuad, c: u32) -> u32 {
    let i = q.i + (c & 1) * q.size;
    let j = q.j + (c >> 1) * q.size;
    j * 17 + i
}

/// Lattice index of new point n (0..4) of the parent quad whose first child is q, as `probe_point` in WGSL.
pub fn probe_point(q: &crate::gpu::structs::GpuQuad, n: u32) -> u32 {
    let h = q.size;
    let (i, j) = [
        (q.i + h, q.j),
        (q.i, q.j + h),
        (q.i + h, q.j + h),
        (q.i + 2 * h, q.j + h),
        (q.i + h, q.j + 2 * h),
    ][n as usize];
    j * 17 + i
}
