// probe (scope = local): closes the blind spot of region-local refinement. A pixel whose four
// corners of a quad agree (c = 0 or 4) while that quad was split for other pixels tests the quad's
// five new samples, which the level has just rendered anyway. If they agree with the corners, the
// quad adds its uniform share c/4 * area(q); if any disagrees, the pixel enters the four children
// as ordinary items of this level (method.md §4.3). No raster is added.
//  begin: the probes compact appended become this level's work; main: one probe each, reading the
//  five samples' lit bits, which shadow_test `probes` has just cached in the lattice masks.

@group(0) @binding(1) var<uniform> level: GpuLevel;
// (pixel, first child | lit << 31): lit = the parent's corners all lit (c = 4), else all unlit.
@group(0) @binding(2) var<storage, read> probes: array<vec2<u32>>;
@group(0) @binding(3) var<storage, read> quads: array<GpuQuad>;
// Bit k of pixel p's word p * MASK_WORDS + k / 32: lattice sample k lights p (tested samples only).
@group(0) @binding(4) var<storage, read> masks: array<u32>;
@group(0) @binding(9) var<storage, read_write> items: array<vec2<u32>>;
@group(0) @binding(10) var<storage, read_write> control: GpuControl;
@group(0) @binding(11) var<storage, read_write> visibility_fixed: array<atomic<u32>>;
@group(0) @binding(13) var<storage, read_write> probe_total: array<u32>;
@group(0) @binding(14) var<storage, read_write> probe_args: array<u32>;

var<workgroup> group_items: atomic<u32>;
var<workgroup> group_base: u32;

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let index = list_index(gid);
    let valid = index < probe_total[0];
    var expand = false;
    var local_slot = 0u;
    var probe = vec2<u32>(0u, 0u);
    if (valid) {
        probe = probes[index];
        let p = probe.x;
        let base = probe.y & ~PROBE_LIT;
        let expect = select(0u, 1u, (probe.y & PROBE_LIT) != 0u);
        // The parent's five new samples: the children's corners that are not the parent's.
        let q = quads[base];
        for (var n = 0u; n < 5u; n = n + 1u) {
            let k = probe_point(q, n);
            if (((masks[p * MASK_WORDS + k / 32u] >> (k % 32u)) & 1u) != expect) {
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
    let args = list_dispatch(n);
    probe_args[0] = args.x;
    probe_args[1] = args.y;
    probe_args[2] = args.z;
    atomicStore(&control.probe_count, 0u);
}
