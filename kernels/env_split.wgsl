// env_split: env-adaptive's splitting. A cell splits into its four quadrants when it carries at
// least min_share of the panorama's power and either more than p_m pixels saw its corners disagree
// (visibility) or its quadrants' powers differ by more than `contrast` (radiance); otherwise it is a
// leaf. Children and leaves are appended with atomics (docs/environment.md §2).

@group(0) @binding(0) var<uniform> params: GpuEnvParams;
@group(0) @binding(1) var<storage, read> cells: array<GpuEnvCell>;
@group(0) @binding(2) var<storage, read> counts: array<u32>;
@group(0) @binding(3) var<storage, read> cell_power: array<f32>;
@group(0) @binding(4) var<storage, read_write> next_cells: array<GpuEnvCell>;
@group(0) @binding(5) var<storage, read_write> leaves: array<GpuEnvCell>;
// 0: next cells, 1: leaves.
@group(0) @binding(6) var<storage, read_write> control: array<atomic<u32>, 4>;

// Power of the finest cells [i, i + size) × [j, j + size).
fn region_power(i: u32, j: u32, size: u32) -> f32 {
    var sum = 0.0;
    for (var y = j; y < j + size; y = y + 1u) {
        for (var x = i; x < i + size; x = x + 1u) {
            sum = sum + cell_power[y * params.finest_width + x];
        }
    }
    return sum;
}

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.cell_count) {
        return;
    }
    let cell = cells[gid.x];
    var split = false;
    if (cell.level < params.max_level && cell.size > 1u) {
        let half = cell.size / 2u;
        let p0 = region_power(cell.i, cell.j, half);
        let p1 = region_power(cell.i + half, cell.j, half);
        let p2 = region_power(cell.i, cell.j + half, half);
        let p3 = region_power(cell.i + half, cell.j + half, half);
        let total = p0 + p1 + p2 + p3;
        let lo = min(min(p0, p1), min(p2, p3));
        let hi = max(max(p0, p1), max(p2, p3));
        if (total >= params.min_share * params.total_power && total > 0.0) {
            split = counts[gid.x] > params.p_m || hi > params.contrast * lo;
        }
    }
    if (split) {
        let half = cell.size / 2u;
        let base = atomicAdd(&control[0], 4u);
        for (var c = 0u; c < 4u; c = c + 1u) {
            next_cells[base + c] = GpuEnvCell(cell.i + (c & 1u) * half, cell.j + (c >> 1u) * half, half, cell.level + 1u);
        }
    } else {
        let k = atomicAdd(&control[1], 1u);
        leaves[k] = cell;
    }
}
