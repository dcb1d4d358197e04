// subdivide: one workgroup reads every active quad's counter, records the deepest evaluated level
// of each corner sample (the seed's weights), splits quads with count > P_M (or always / never),
// (split_mode 3: count > split_share x geometry pixels, in f32 as the twin computes it),
// appends the children and the new lattice samples (deduplicated with atomicOr: the thread that
// sees the old value 0 appends), and writes the next level's dispatch arguments.
// Hysteresis (`hold`, docs/reuse.md): a quad the previous frame did not split (its bit in `held`
// clear) needs `level.hold` more low-quality pixels than the threshold; one it split does not.

@group(0) @binding(0) var<uniform> level: GpuLevel;
@group(0) @binding(1) var<storage, read> quads: array<GpuQuad>;
@group(0) @binding(2) var<storage, read> quad_counters: array<u32>;
@group(0) @binding(3) var<storage, read_write> next_quads: array<GpuQuad>;
@group(0) @binding(4) var<storage, read_write> control: GpuControl;
@group(0) @binding(5) var<storage, read_write> lattice_state: array<atomic<u32>>;
@group(0) @binding(6) var<storage, read_write> new_samples: array<u32>;
@group(0) @binding(7) var<storage, read_write> sample_level: array<atomic<u32>>;
@group(0) @binding(8) var<storage, read_write> split_base: array<u32>;
@group(0) @binding(9) var<storage, read_write> dispatch_args: array<u32>;
@group(0) @binding(10) var<storage, read> held: array<u32>;

// A quad's place among every level's quads (0..341): the coarser levels' (4^d - 1) / 3 first,
// then its row and column at its own level.
fn quad_node(quad: GpuQuad) -> u32 {
    let side = 16u / quad.size;
    return (side * side - 1u) / 3u + (quad.j / quad.size) * side + quad.i / quad.size;
}

// The margin a quad's count must pass its threshold by: 0 for a quad the previous frame split.
fn hold_margin(quad: GpuQuad) -> u32 {
    let node = quad_node(quad);
    let split_before = (held[node / 32u] >> (node % 32u)) & 1u;
    return select(level.hold, 0u, split_before == 1u);
}

fn request(i: u32, j: u32) {
    let k = j * LATTICE_SIDE + i;
    if (atomicOr(&lattice_state[k], 1u) == 0u) {
        let slot = atomicAdd(&control.new_sample_count, 1u);
        new_samples[slot] = k;
    }
}

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(local_invocation_index) lid: u32) {
    let share_threshold = f32(atomicLoad(&control.geometry_pixels)) * level.split_share;
    for (var q = lid; q < level.quad_count; q = q + 64u) {
        let quad = quads[q];
        for (var c = 0u; c < 4u; c = c + 1u) {
            atomicMax(&sample_level[quad_corner(quad, c)], level.level);
        }
        var split = false;
        if (level.level < level.max_level && quad.size > 1u) {
            // count - threshold > margin without overflow; (count - margin) > share x N with no
            // product in the subtraction, so no fused multiply-add can round it apart from the twin.
            let margin = hold_margin(quad);
            let count = quad_counters[q];
            split = level.split_mode == SPLIT_ALWAYS
                || (level.split_mode == SPLIT_THRESHOLD && count > level.split_threshold && count - level.split_threshold > margin)
                || (level.split_mode == SPLIT_SHARE && f32(count) - f32(margin) > share_threshold);
        }
        split_base[q] = NO_SPLIT;
        if (split) {
            let base = atomicAdd(&control.next_quad_count, 4u);
            if (base + 4u > level.quad_capacity) {
                atomicOr(&control.overflow, OVERFLOW_QUADS);
            } else {
                let h = quad.size / 2u;
                next_quads[base] = GpuQuad(quad.i, quad.j, h, q);
                next_quads[base + 1u] = GpuQuad(quad.i + h, quad.j, h, q);
                next_quads[base + 2u] = GpuQuad(quad.i, quad.j + h, h, q);
                next_quads[base + 3u] = GpuQuad(quad.i + h, quad.j + h, h, q);
                split_base[q] = base;
                request(quad.i + h, quad.j);
                request(quad.i, quad.j + h);
                request(quad.i + h, quad.j + h);
                request(quad.i + 2u * h, quad.j + h);
                request(quad.i + h, quad.j + 2u * h);
            }
        }
    }
    workgroupBarrier();
    storageBarrier();
    if (lid == 0u) {
        let next = min(atomicLoad(&control.next_quad_count), level.quad_capacity);
        dispatch_args[0] = level.dense_groups_x;
        dispatch_args[1] = next;
        dispatch_args[2] = 1u;
    }
}
