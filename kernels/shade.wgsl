// shade: V(p) += sum over this chunk's samples of weight_i * lit_i(p). Chunks (one per shadow-map
// array or budget slice) accumulate in order, so the sum order is fixed and the CPU twin matches.

struct GpuShadeChunk {
    first_sample: u32,
    sample_count: u32,
    pad0: u32,
    pad1: u32,
}

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> chunk: GpuShadeChunk;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var<storage, read> weights: array<f32>;
@group(0) @binding(4) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(5) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(6) var shadow_maps: ShadowMaps;
@group(0) @binding(7) var<storage, read_write> visibility: array<f32>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    let pixel = vec2<i32>(gid.xy);
    let position = textureLoad(gbuffer_position, pixel, 0);
    if (position.w == 0.0) {
        return;
    }
    let normal = textureLoad(gbuffer_normal, pixel, 0).xyz;
    let index = gid.y * frame.width + gid.x;
    var v = visibility[index];
    for (var i = 0u; i < chunk.sample_count; i = i + 1u) {
        let s = samples[chunk.first_sample + i];
        let lookup = shadow_lookup(frame, s, position.xyz, normal);
        let stored = map_depth(frame, shadow_maps, s, lookup.texel);
        v = v + weights[chunk.first_sample + i] * f32(shadow_compare(s, lookup, stored));
    }
    visibility[index] = v;
}

// Adaptive (scope = global): V(p) = Σ_k ŵ_k · bit_k(p) over the lattice masks, k ascending, so the
// sum order equals the regular grid's when every lattice sample is used.
@group(0) @binding(8) var<storage, read> masks: array<u32>;

@compute @workgroup_size(8, 8, 1)
fn from_masks(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    if (textureLoad(gbuffer_position, vec2<i32>(gid.xy), 0).w == 0.0) {
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
