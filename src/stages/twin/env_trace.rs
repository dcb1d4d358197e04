//! Twin of `kernels/env_trace.wgsl` (with the BVH test of src/render/bvh.rs).

use crate::gpu::structs::{GpuEnvLight, GpuEnvParams};
use crate::render::bvh::Bvh;
use crate::render::gbuffer::GBufferCpu;
use crate::scene::Vertex;

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The ray origin: p + n · offset, per component as WGSL's `p + n * offset`.
pub fn origin(p: [f32; 3], n: [f32; 3], offset: f32) -> [f32; 3] {
    [
        p[0] + n[0] * offset,
        p[1] + n[1] * offset,
        p[2] + n[2] * offset,
    ]
}

/// (Σ power·cos·vis, Σ power·cos, blocked rays) of the lights from origin `o` over normal `n`, as
/// `trace_chunk` sums them chunk after chunk.
fn light_sums(
    params: &GpuEnvParams,
    o: [f32; 3],
    n: [f32; 3],
    lights: &[GpuEnvLight],
    bvh: &Bvh,
) -> (f32, f32, u32) {
    let (mut num, mut den, mut blocked) = (0.0f32, 0.0f32, 0u32);
    for l in &lights[..params.light_count as usize] {
        let d = [l.direction[0], l.direction[1], l.direction[2]];
        let c = dot(n, d);
        if c <= 0.0 {
            continue;
        }
        let w = l.direction[3] * c;
        den += w;
        if bvh.occluded(o, d, params.t_max) {
            blocked += 1;
        } else {
            num += w;
        }
    }
    (num, den, blocked)
}

/// (V, blocked rays) per mesh vertex, as the `vertex` entry point: the vertex's position and
/// normal, the origin offset along the normal.
pub fn env_trace_vertices(
    params: &GpuEnvParams,
    vertices: &[Vertex],
    lights: &[GpuEnvLight],
    bvh: &Bvh,
) -> (Vec<f32>, Vec<u32>) {
    vertices
        .iter()
        .map(|v| {
            let (num, den, blocked) = light_sums(
                params,
                origin(v.position, v.normal, params.ray_offset),
                v.normal,
                lights,
                bvh,
            );
            (if den > 0.0 { num / den } else { 0.0 }, blocked)
        })
        .unzip()
}

/// (V, blocked rays) per pixel; background pixels are left at 0.
pub fn env_trace(
    params: &GpuEnvParams,
    g: &GBufferCpu,
    lights: &[GpuEnvLight],
    ao: &[f32],
    bvh: &Bvh,
) -> (Vec<f32>, Vec<u32>) {
    let count = g.position.len();
    let mut visibility = vec![0.0f32; count];
    let mut blocked = vec![0u32; count];
    for index in 0..count {
        if !g.is_geometry(index) {
            continue;
        }
        let p = [
            g.position[index][0],
            g.position[index][1],
            g.position[index][2],
        ];
        let n = [g.normal[index][0], g.normal[index][1], g.normal[index][2]];
        let (num, den, c_blocked) =
            light_sums(params, origin(p, n, params.ray_offset), n, lights, bvh);
        let mut v = if den > 0.0 { num / den } else { 0.0 };
        if params.use_ao != 0 {
            v *= ao[index];
        }
        visibility[index] = v;
        blocked[index] = c_blocked;
    }
    (visibility, blocked)
}
