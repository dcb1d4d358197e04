// shade: V(p) += sum over this chunk's samples of weight_i * lit_i(p). Chunks (one per shadow-map
// array or budget slice) accumulate in order, so the sum order is fixed and the CPU twin matches.

// One dispatch per block of consecutive samples: SHADE_BLOCK of them, and for the last part of a
// range its binary decomposition (8, 4, 2, 1), one entry point per size, in sample order. Every
// block is full, so no lane looks up a sample past the range's end (a CPU device computes masked
// lanes anyway: 25 samples as 16 + 16 cost 32 lookups, as 16 + 8 + 1 they cost 25).

// The block's samples and weights are copied into uniform buffers and the block is unrolled, so
// every read has a constant offset: a CPU device loads it once per SIMD row, as long as no branch
// is open around the read (see shade_block). Read from a storage buffer at a loop counter's index,
// each sample was gathered lane by lane and component by component. Rust's SHADE_BLOCK
// (src/stages/shade.rs) is this number.
const SHADE_BLOCK: u32 = 16u;

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> block_samples: array<GpuSample, SHADE_BLOCK>;
// Weight j of the block is block_weights[j / 4][j % 4] (uniform arrays have a 16-byte stride).
@group(0) @binding(2) var<uniform> block_weights: array<vec4<f32>, 4>;
@group(0) @binding(3) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(5) var shadow_maps: ShadowMaps;
@group(0) @binding(6) var<storage, read_write> visibility: array<f32>;

// v + weight_j · lit_j(p) for the block's sample j.
fn add1(v: f32, j: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let s = block_samples[j];
    let lookup = shadow_lookup(frame, s, p, n);
    let stored = map_depth(frame, shadow_maps, s, lookup.texel);
    return v + block_weights[j / 4u][j % 4u] * f32(shadow_compare(s, lookup, stored));
}

// Samples j .. j + 2^k, each added in turn: the additions of a plain loop, in its order.
fn add2(v: f32, j: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    return add1(add1(v, j, p, n), j + 1u, p, n);
}

fn add4(v: f32, j: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    return add2(add2(v, j, p, n), j + 2u, p, n);
}

fn add8(v: f32, j: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    return add4(add4(v, j, p, n), j + 4u, p, n);
}

fn add16(v: f32, j: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    return add8(add8(v, j, p, n), j + 8u, p, n);
}

// Adds the block's first `count` samples (a constant in every entry point, so each unrolls).
// No early return: on a CPU device the code after a branch runs under a lane mask, and under a
// mask Mesa's llvmpipe reads even a constant-offset uniform lane by lane, with a bounds check per
// lane (the samples' reads were then most of the stage's instructions). Pixels outside the image
// or without geometry compute like the others; only their store is skipped.
fn shade_block(gid: vec3<u32>, count: u32) {
    let inside = gid.x < frame.width && gid.y < frame.height;
    let pixel = vec2<i32>(gid.xy);
    let position = textureLoad(gbuffer_position, pixel, 0);
    let p = position.xyz;
    let n = textureLoad(gbuffer_normal, pixel, 0).xyz;
    let index = gid.y * frame.width + gid.x - band_base(frame);
    var v = visibility[index];
    switch (count) {
        case 16u: { v = add16(v, 0u, p, n); }
        case 8u: { v = add8(v, 0u, p, n); }
        case 4u: { v = add4(v, 0u, p, n); }
        case 2u: { v = add2(v, 0u, p, n); }
        default: { v = add1(v, 0u, p, n); }
    }
    if (inside && position.w != 0.0) {
        visibility[index] = v;
    }
}

// ---- geometry tiles (kernels/shared/common.wgsl) ----
@group(0) @binding(10) var<storage, read_write> tile_list_build: array<atomic<u32>>;
@group(0) @binding(11) var<storage, read> tile_list: array<u32>;

var<workgroup> tile_has_geometry: atomic<u32>;

@compute @workgroup_size(8, 8, 1)
fn geometry_tiles(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lid: u32, @builtin(num_workgroups) groups: vec3<u32>) {
    let inside = gid.x < frame.width && gid.y < frame.height;
    let w = textureLoad(gbuffer_position, vec2<i32>(gid.xy), 0).w;
    if (inside && w != 0.0) {
        atomicOr(&tile_has_geometry, 1u);
    }
    workgroupBarrier();
    if (lid == 0u && atomicLoad(&tile_has_geometry) != 0u) {
        // The section of the tile's band (bands are whole tiles high; one section without bands).
        let section = select(0u, group.y * 8u / max(frame.band_rows, 1u), frame.band_rows != 0u) * frame.tile_section_words;
        let slot = atomicAdd(&tile_list_build[section], 1u);
        atomicStore(&tile_list_build[section + TILE_LIST_HEADER + slot], group.y * groups.x + group.x);
    }
}

@compute @workgroup_size(8, 8, 1)
fn block16(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    shade_block(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width), 16u);
}

@compute @workgroup_size(8, 8, 1)
fn block8(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    shade_block(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width), 8u);
}

@compute @workgroup_size(8, 8, 1)
fn block4(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    shade_block(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width), 4u);
}

@compute @workgroup_size(8, 8, 1)
fn block2(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    shade_block(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width), 2u);
}

@compute @workgroup_size(8, 8, 1)
fn block1(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    shade_block(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width), 1u);
}

// Adaptive (scope = global): V(p) = Σ_k ŵ_k · bit_k(p) over the lattice masks, k ascending, so the
// sum order equals the regular grid's when every lattice sample is used.
@group(0) @binding(7) var<storage, read> masks: array<u32>;
@group(0) @binding(8) var<storage, read> weights: array<f32>;

@compute @workgroup_size(8, 8, 1)
fn from_masks(@builtin(global_invocation_id) gid: vec3<u32>) {
    // One dispatch per band: rows band_first_row .. + band_height; masks and V bound from its start.
    let y = gid.y + frame.band_first_row;
    if (gid.x >= frame.width || gid.y >= band_height(frame)) {
        return;
    }
    if (textureLoad(gbuffer_position, vec2<i32>(i32(gid.x), i32(y)), 0).w == 0.0) {
        return;
    }
    let index = gid.y * frame.width + gid.x;
    // Only the set bits are visited (lowest first), so the additions are the same, in the same
    // order, as a loop over all 289 k; the summary flags above bit 288 are masked off.
    var v = 0.0;
    for (var w = 0u; w < MASK_WORDS; w = w + 1u) {
        var bits = masks[index * MASK_WORDS + w];
        if (w == LATTICE_POINTS / 32u) {
            bits = bits & ((1u << (LATTICE_POINTS % 32u)) - 1u);
        }
        while (bits != 0u) {
            v = v + weights[w * 32u + firstTrailingBit(bits)];
            bits = bits & (bits - 1u);
        }
    }
    visibility[index] = v;
}
