//! Twin of `kernels/env_count.wgsl`.

use super::env_trace::origin;
use crate::gpu::structs::{GpuEnvCell, GpuEnvParams};
use crate::render::bvh::Bvh;
use crate::render::gbuffer::GBufferCpu;

/// Per cell, the pixels whose rays to the cell's corners above their tangent plane disagree.
pub fn env_count(
    params: &GpuEnvParams,
    g: &GBufferCpu,
    corners: &[[f32; 4]],
    cells: &[GpuEnvCell],
    bvh: &Bvh,
) -> Vec<u32> {
    let mut counts = vec![0u32; cells.len()];
    let stride = params.count_stride.max(1);
    for index in 0..g.position.len() {
        let (x, y) = (index as u32 % params.width, index as u32 / params.width);
        if !g.is_geometry(index) || x % stride != 0 || y % stride != 0 {
            continue;
        }
        let p = [
            g.position[index][0],
            g.position[index][1],
            g.position[index][2],
        ];
        let n = [g.normal[index][0], g.normal[index][1], g.normal[index][2]];
        let o = origin(p, n, params.ray_offset);
        for (k, cell) in cells.iter().enumerate() {
            let (mut valid, mut lit) = (0u32, 0u32);
            for c in 0..4u32 {
                let i = cell.i + (c & 1) * cell.size;
                let j = cell.j + (c >> 1) * cell.size;
                let d = corners[(j * (params.finest_width + 1) + i) as usize];
                let d = [d[0], d[1], d[2]];
                if n[0] * d[0] + n[1] * d[1] + n[2] * d[2] <= 0.0 {
                    continue;
                }
                valid += 1;
                if !bvh.occluded(o, d, params.t_max) {
                    lit += 1;
                }
            }
            if lit > 0 && lit < valid {
                counts[k] += 1;
            }
        }
    }
    counts
}
