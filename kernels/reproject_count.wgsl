// reproject_count: c_q(p) in 0..4, the number of quad q's corner samples that light pixel p,
// stored as c + 1 in one byte per pixel (4 per word) of q's comparison map.
//  main: every pixel x every active quad, from the cached lattice masks (scope = global);
//  list: the compacted (pixel, quad) items only, testing the corner maps directly (scope = local).
// At level 0 both also count the geometry pixels (the share criteria's denominator, method.md §6):
// level 0 has one quad, which every geometry pixel meets exactly once.

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> level: GpuLevel;
@group(0) @binding(2) var<storage, read> quads: array<GpuQuad>;
@group(0) @binding(3) var<storage, read> masks: array<u32>;
@group(0) @binding(4) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(5) var<storage, read_write> counts: array<u32>;
// (main reads the G-buffer only through the mask summaries; list reads it directly.)

@group(0) @binding(6) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(7) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(8) var maps_a: texture_depth_2d_array;
@group(0) @binding(9) var maps_b: texture_depth_2d_array;
@group(0) @binding(10) var<storage, read> items: array<vec2<u32>>;
@group(0) @binding(11) var<storage, read_write> counts_atomic: array<atomic<u32>>;
@group(0) @binding(12) var<storage, read_write> consulted: array<atomic<u32>>;
@group(0) @binding(13) var<storage, read> item_total: array<u32>;
@group(0) @binding(14) var<storage, read_write> control: GpuControl;
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

// Counts one word's 4 pixels for every quad of the batch; returns its geometry pixels.
fn count_word(word: u32) -> u32 {
    let words = frame.height * level.words_per_row;
    if (word >= words) {
        return 0u;
    }
    let gid = vec3<u32>(word, 0u, 0u);
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
            let summary = masks[p * MASK_WORDS + SUMMARY_WORD];
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
                    c = c + ((masks[p * MASK_WORDS + k / 32u] >> (k % 32u)) & 1u);
                }
                packed = packed | ((c + 1u) << (b * 8u));
            }
        }
        counts[qi * words + gid.x] = packed;
    }
    return geometry;
}

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

@compute @workgroup_size(64, 1, 1)
fn list(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let valid = gid.x < item_total[0];
    if (valid) {
        count_item(gid.x);
    }
    add_geometry(select(0u, 1u, valid), lid);
}

fn count_item(index: u32) {
    let item = items[index];
    let p = item.x;
    let q = quads[item.y];
    let pixel = vec2<i32>(i32(p % frame.width), i32(p / frame.width));
    let position = textureLoad(gbuffer_position, pixel, 0).xyz;
    let normal = textureLoad(gbuffer_normal, pixel, 0).xyz;
    var c = 0u;
    for (var corner = 0u; corner < 4u; corner = corner + 1u) {
        let k = quad_corner(q, corner);
        c = c + lit_lattice(k, position, normal);
        atomicOr(&consulted[p * MASK_WORDS + k / 32u], 1u << (k % 32u));
    }
    let words = frame.height * level.words_per_row;
    let x = p % frame.width;
    let y = p / frame.width;
    atomicOr(&counts_atomic[item.y * words + y * level.words_per_row + x / 4u], (c + 1u) << ((x & 3u) * 8u));
}
