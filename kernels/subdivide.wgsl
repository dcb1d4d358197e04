// subdivide: one workgroup reads every active quad's counter, records the deepest evaluated level
// of each corner sample (the seed's weights), splits quads with count > P_M (or always / never),
// (split_mode 3: count > split_share x geometry pixels, in f32 as the twin computes it),
// appends the children and the new lattice samples (deduplicated with atomicOr: the thread that
// sees the old value 0 appends), and writes the next level's dispatch arguments.

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
            split = level.split_mode == SPLIT_ALWAYS
                || (level.split_mode == SPLIT_THRESHOLD && quad_counters[q] > level.split_threshold)
                || (level.split_mode == SPLIT_SHARE && f32(quad_counters[q]) > share_threshold);
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
