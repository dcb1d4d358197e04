// probe (scope = local): closes the blind spot of region-local refinement. A pixel whose four
// corners of a quad agree (c = 0 or 4) while that quad was split for other pixels tests the quad's
// five new samples, which the level has just rendered anyway. If they agree with the corners, the
// quad adds its uniform share c/4 * area(q); if any disagrees, the pixel enters the four children
// as ordinary items of this level (method.md §4.3). No raster is added.
//  begin: the probes compact appended become this level's work; main: one probe each.

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> level: GpuLevel;
// (pixel, first child | lit << 31): lit = the parent's corners all lit (c = 4), else all unlit.
@group(0) @binding(2) var<storage, read> probes: array<vec2<u32>>;
@group(0) @binding(3) var<storage, read> quads: array<GpuQuad>;
@group(0) @binding(4) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(5) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(6) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(7) var maps_a: texture_depth_2d_array;
@group(0) @binding(8) var maps_b: texture_depth_2d_array;
@group(0) @binding(9) var<storage, read_write> items: array<vec2<u32>>;
@group(0) @binding(10) var<storage, read_write> control: GpuControl;
@group(0) @binding(11) var<storage, read_write> visibility_fixed: array<atomic<u32>>;
@group(0) @binding(12) var<storage, read_write> consulted: array<atomic<u32>>;
@group(0) @binding(13) var<storage, read_write> probe_total: array<u32>;
@group(0) @binding(14) var<storage, read_write> probe_args: array<u32>;

const PROBE_LIT: u32 = 0x80000000u;

fn lit_lattice(k: u32, position: vec3<f32>, normal: vec3<f32>) -> u32 {
    let s = samples[k];
    let lookup = shadow_lookup(frame, s, position, normal);
    var stored: f32;
    if (s.array == 0u) {
        stored = textureLoad(maps_a, lookup.texel, i32(s.layer), 0);
    } else {
        stored = textureLoad(maps_b, lookup.texel, i32(s.layer), 0);
    }
    return shadow_compare(s, lookup, stored);
}

var<workgroup> group_items: atomic<u32>;
var<workgroup> group_base: u32;

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let valid = gid.x < probe_total[0];
    var expand = false;
    var local_slot = 0u;
    var probe = vec2<u32>(0u, 0u);
    if (valid) {
        probe = probes[gid.x];
        let p = probe.x;
        let base = probe.y & ~PROBE_LIT;
        let expect = select(0u, 1u, (probe.y & PROBE_LIT) != 0u);
        let pixel = vec2<i32>(i32(p % frame.width), i32(p / frame.width));
        let position = textureLoad(gbuffer_position, pixel, 0).xyz;
        let normal = textureLoad(gbuffer_normal, pixel, 0).xyz;
        // The parent's five new samples: the children's corners that are not the parent's.
        let q = quads[base];
        let h = q.size;
        let new_points = array<vec2<u32>, 5>(
            vec2<u32>(q.i + h, q.j), vec2<u32>(q.i, q.j + h), vec2<u32>(q.i + h, q.j + h),
            vec2<u32>(q.i + 2u * h, q.j + h), vec2<u32>(q.i + h, q.j + 2u * h));
        for (var n = 0u; n < 5u; n = n + 1u) {
            let k = new_points[n].y * LATTICE_SIDE + new_points[n].x;
            atomicOr(&consulted[p * MASK_WORDS + k / 32u], 1u << (k % 32u));
            if (lit_lattice(k, position, normal) != expect) {
                expand = true;
            }
        }
        if (expand) {
            local_slot = atomicAdd(&group_items, 4u);
        } else if (expect == 1u) {
            // The parent (level - 1) is uniformly lit: c = 4 at its weight 4^(max_level - level + 1).
            atomicAdd(&visibility_fixed[p], 4u << (2u * (level.max_level - level.level + 1u)));
        }
    }
    workgroupBarrier();
    if (lid == 0u) {
        group_base = atomicAdd(&control.item_count, atomicLoad(&group_items));
    }
    let slot = workgroupUniformLoad(&group_base) + local_slot;
    if (!expand) {
        return;
    }
    if (slot + 4u > level.item_capacity) {
        atomicOr(&control.overflow, OVERFLOW_ITEMS);
        return;
    }
    let base = probe.y & ~PROBE_LIT;
    for (var child = 0u; child < 4u; child = child + 1u) {
        items[slot + child] = vec2<u32>(probe.x, base + child);
    }
}

// Starts the level's probes: count and dispatch size from the append counter, which restarts.
@compute @workgroup_size(1, 1, 1)
fn begin() {
    let n = min(atomicLoad(&control.probe_count), level.item_capacity);
    probe_total[0] = n;
    probe_args[0] = (n + 63u) / 64u;
    probe_args[1] = 1u;
    probe_args[2] = 1u;
    atomicStore(&control.probe_count, 0u);
}
