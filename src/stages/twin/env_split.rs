//! Twin of `kernels/env_split.wgsl`: (children, leaves), each sorted (the GPU appends in any order).

use crate::gpu::structs::{GpuEnvCell, GpuEnvParams};

fn region_power(params: &GpuEnvParams, cell_power: &[f32], i: u32, j: u32, size: u32) -> f32 {
    let mut sum = 0.0f32;
    for y in j..j + size {
        for x in i..i + size {
            sum += cell_power[(y * params.finest_width + x) as usize];
        }
    }
    sum
}

/// Whether `cell` splits: the kernel's rule.
pub fn splits(params: &GpuEnvParams, cell: &GpuEnvCell, count: u32, cell_power: &[f32]) -> bool {
    if cell.level >= params.max_level || cell.size <= 1 {
        return false;
    }
    let half = cell.size / 2;
    let p = [
        region_power(params, cell_power, cell.i, cell.j, half),
        region_power(params, cell_power, cell.i + half, cell.j, half),
        region_power(params, cell_power, cell.i, cell.j + half, half),
        region_power(params, cell_power, cell.i + half, cell.j + half, half),
    ];
    let total = p[0] + p[1] + p[2] + p[3];
    let lo = p[0].min(p[1]).min(p[2].min(p[3]));
    let hi = p[0].max(p[1]).max(p[2].max(p[3]));
    total >= params.min_share * params.total_power
        && total > 0.0
        && (count > params.p_m || hi > params.contrast * lo)
}

pub fn env_split(
    params: &GpuEnvParams,
    cells: &[GpuEnvCell],
    counts: &[u32],
    cell_power: &[f32],
) -> (Vec<GpuEnvCell>, Vec<GpuEnvCell>) {
    let (mut next, mut leaves) = (Vec::new(), Vec::new());
    for (k, cell) in cells.iter().enumerate() {
        if splits(params, cell, counts[k], cell_power) {
            let half = cell.size / 2;
            for c in 0..4u32 {
                next.push(GpuEnvCell {
                    i: cell.i + (c & 1) * half,
                    j: cell.j + (c >> 1) * half,
                    size: half,
                    level: cell.level + 1,
                });
            }
        } else {
            leaves.push(*cell);
        }
    }
    next.sort();
    leaves.sort();
    (next, leaves)
}
