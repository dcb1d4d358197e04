// reproject_count: c_q(p) in 0..4, the number of quad q's corner samples that light pixel p,
// stored as c + 1 in one byte per pixel (4 per word) of q's comparison map.
//  main: every pixel x every active quad, from the cached lattice masks (scope = global);
//  list: the compacted (pixel, quad) items only (scope = local), from the lattice masks that
//  shadow_test `list` has just filled with each item's corner samples; begin starts its level;
//  last: the last level's items, whose counts add to V at once (nothing splits there).
// At level 0 main also counts the geometry pixels (the share criteria's denominator, method.md §6);
// under scope = local compact `seed` counts them as it lists them.

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> level: GpuLevel;
@group(0) @binding(2) var<storage, read> quads: array<GpuQuad>;
@group(0) @binding(3) var<storage, read> masks: array<u32>;
@group(0) @binding(5) var<storage, read_write> counts: array<u32>;
// (Neither reads the G-buffer: main finds geometry in the mask summaries, list is given its pixels.)

@group(0) @binding(10) var<storage, read> items: array<vec2<u32>>;
@group(0) @binding(11) var<storage, read_write> counts_atomic: array<atomic<u32>>;
// last: V's exact integer sums (compact.wgsl), to which each item adds its quad's uniform share.
@group(0) @binding(12) var<storage, read_write> visibility_fixed: array<atomic<u32>>;
@group(0) @binding(13) var<storage, read_write> item_total: array<u32>;
@group(0) @binding(14) var<storage, read_write> control: GpuControl;
// begin: the indirect dispatch size of the level's item passes (list, neighbourhood, compact).
@group(0) @binding(16) var<storage, read_write> list_args: array<u32>;
// main: each word's state (common.wgsl MIXED_WORD): uniform words are written here once, not per quad.
@group(0) @binding(15) var<storage, read_write> word_state: array<u32>;

var<workgroup> group_geometry: atomic<u32>;

// One global atomic per workgroup. `level` is uniform, so the barrier is in uniform control flow.
fn add_geometry(n: u32, lid: u32) {
    if (level.level != 0u) {
        return;
    }
    if (n != 0u) {
        atomicAdd(&group_geometry, n);
    }
    workgroupBarrier();
    if (lid == 0u) {
        let total = atomicLoad(&group_geometry);
        if (total != 0u) {
            atomicAdd(&control.geometry_pixels, total);
        }
    }
}

// One thread per word (4 pixels) counts every active quad of the batch (the quads loop inside the
// thread), so each pixel's summary is read once. A word whose pixels every map agrees on has the
// same bytes for every quad: it costs one word_state store, and its comparison-map words are not
// written (neighbourhood reads word_state first).
@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    add_geometry(count_word(gid.x), lid);
}

// Counts one word's 4 pixels for every quad of the batch; returns its geometry pixels. `word`
// counts from the dispatch's band (masks are bound from its first pixel); the comparison maps
// and word states cover the whole image.
fn count_word(word: u32) -> u32 {
    let words = frame.height * level.words_per_row;
    if (word >= band_height(frame) * level.words_per_row) {
        return 0u;
    }
    let gid = vec3<u32>(word + frame.band_first_row * level.words_per_row, 0u, 0u);
    let base = band_base(frame);
    var geometry = 0u;
    let y = gid.x / level.words_per_row;
    let wx = gid.x % level.words_per_row;
    // Pixels every map agrees on have the same byte for every quad: 1 (c = 0) or 5 (c = 4).
    var uniform_bytes = 0u;
    var mixed = 0u;
    for (var b = 0u; b < 4u; b = b + 1u) {
        let x = wx * 4u + b;
        if (x < frame.width) {
            let p = y * frame.width + x;
            let summary = masks[(p - base) * MASK_WORDS + SUMMARY_WORD];
            let all_lit = (summary & SUMMARY_ANY_UNLIT) == 0u;
            let all_unlit = (summary & SUMMARY_ANY_LIT) == 0u;
            if ((summary & SUMMARY_GEOMETRY) == 0u) {
                // background: byte 0
                continue;
            }
            geometry = geometry + 1u;
            if (all_lit || all_unlit) {
                uniform_bytes = uniform_bytes | (select(1u, 5u, all_lit) << (b * 8u));
            } else {
                mixed = mixed | (1u << b);
            }
        }
    }
    word_state[gid.x] = select(uniform_bytes, MIXED_WORD, mixed != 0u);
    if (mixed == 0u) {
        return geometry;
    }
    for (var qi = 0u; qi < level.quad_count; qi = qi + 1u) {
        let q = quads[level.first_quad + qi];
        var packed = uniform_bytes;
        for (var b = 0u; b < 4u; b = b + 1u) {
            if ((mixed & (1u << b)) != 0u) {
                let p = y * frame.width + wx * 4u + b;
                var c = 0u;
                for (var corner = 0u; corner < 4u; corner = corner + 1u) {
                    let k = quad_corner(q, corner);
                    c = c + ((masks[(p - base) * MASK_WORDS + k / 32u] >> (k % 32u)) & 1u);
                }
                packed = packed | ((c + 1u) << (b * 8u));
            }
        }
        counts[qi * words + gid.x] = packed;
    }
    return geometry;
}

// No workgroup barrier here (nor in last): on CPU devices a barrier splits every workgroup into
// resumable pieces, which costs even when the code around it does nothing.
@compute @workgroup_size(64, 1, 1)
fn list(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (list_index(gid) < item_total[0]) {
        count_item(list_index(gid));
    }
}

// c_q(p) of one item: its quad's corner bits in the pixel's lattice mask.
fn item_count(item: vec2<u32>) -> u32 {
    let q = quads[item.y];
    var c = 0u;
    for (var corner = 0u; corner < 4u; corner = corner + 1u) {
        let k = quad_corner(q, corner);
        c = c + ((masks[item.x * MASK_WORDS + k / 32u] >> (k % 32u)) & 1u);
    }
    return c;
}

fn count_item(index: u32) {
    let item = items[index];
    let p = item.x;
    let c = item_count(item);
    let words = frame.height * level.words_per_row;
    let x = p % frame.width;
    let y = p / frame.width;
    atomicOr(&counts_atomic[item.y * words + y * level.words_per_row + x / 4u], (c + 1u) << ((x & 3u) * 8u));
}

// The last level (scope = local): no quad splits there, so no comparison map, neighbourhood or
// compact is needed. Each item adds its quad's uniform share area(q)/area(light) * c/4 to p, as
// compact's resolve does, kept as the integer c * 4^(max_level - level) (= c at max_level).
@compute @workgroup_size(64, 1, 1)
fn last(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (list_index(gid) >= item_total[0]) {
        return;
    }
    let item = items[list_index(gid)];
    let c = item_count(item);
    if (c != 0u) {
        atomicAdd(&visibility_fixed[item.x], c << (2u * (level.max_level - level.level)));
    }
}

// Starts a level (scope = local): the items compact and probe appended become this level's work
// (count and dispatch size), and the append counter restarts, all on the GPU (no read-back).
@compute @workgroup_size(1, 1, 1)
fn begin() {
    let n = min(atomicLoad(&control.item_count), level.item_capacity);
    item_total[0] = n;
    let args = list_dispatch(n);
    list_args[0] = args.x;
    list_args[1] = args.y;
    list_args[2] = args.z;
    atomicStore(&control.item_count, 0u);
}
