// shade: V(p) += sum over this chunk's samples of weight_i * lit_i(p). Chunks (one per shadow-map
// array or budget slice) accumulate in order, so the sum order is fixed and the CPU twin matches.

// One dispatch per block of at most SHADE_BLOCK consecutive samples; GpuShadeChunk is the block
// (first_sample: where the Rust side copied it from, for the record).
struct GpuShadeChunk {
    first_sample: u32,
    sample_count: u32,
    pad0: u32,
    pad1: u32,
}

// The block's samples and weights are copied into uniform buffers and the block is unrolled, so
// every read has a constant offset: a CPU device loads it once per SIMD row. Read from a storage
// buffer at a loop counter's index, each sample was gathered lane by lane and component by
// component (about 30% of the stage on default, docs/bench.md). Rust's SHADE_BLOCK
// (src/compute/shade.rs) is this number.
const SHADE_BLOCK: u32 = 16u;

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> chunk: GpuShadeChunk;
@group(0) @binding(2) var<uniform> block_samples: array<GpuSample, SHADE_BLOCK>;
// Weight j of the block is block_weights[j / 4][j % 4] (uniform arrays have a 16-byte stride).
@group(0) @binding(3) var<uniform> block_weights: array<vec4<f32>, 4>;
@group(0) @binding(4) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(5) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(6) var shadow_maps: ShadowMaps;
@group(0) @binding(7) var<storage, read_write> visibility: array<f32>;

// v + weight_j · lit_j(p) for the block's sample j; j past the block's end adds nothing (the
// select keeps v, and the same addition is made as in a plain loop).
fn add_sample(v: f32, j: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let s = block_samples[j];
    let lookup = shadow_lookup(frame, s, p, n);
    let stored = map_depth(frame, shadow_maps, s, lookup.texel);
    return select(v, v + block_weights[j / 4u][j % 4u] * f32(shadow_compare(s, lookup, stored)), j < chunk.sample_count);
}

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
    let p = position.xyz;
    let n = textureLoad(gbuffer_normal, pixel, 0).xyz;
    let index = gid.y * frame.width + gid.x;
    var v = visibility[index];
    v = add_sample(v, 0u, p, n);
    v = add_sample(v, 1u, p, n);
    v = add_sample(v, 2u, p, n);
    v = add_sample(v, 3u, p, n);
    v = add_sample(v, 4u, p, n);
    v = add_sample(v, 5u, p, n);
    v = add_sample(v, 6u, p, n);
    v = add_sample(v, 7u, p, n);
    v = add_sample(v, 8u, p, n);
    v = add_sample(v, 9u, p, n);
    v = add_sample(v, 10u, p, n);
    v = add_sample(v, 11u, p, n);
    v = add_sample(v, 12u, p, n);
    v = add_sample(v, 13u, p, n);
    v = add_sample(v, 14u, p, n);
    v = add_sample(v, 15u, p, n);
    visibility[index] = v;
}

// Adaptive (scope = global): V(p) = Σ_k ŵ_k · bit_k(p) over the lattice masks, k ascending, so the
// sum order equals the regular grid's when every lattice sample is used.
@group(0) @binding(8) var<storage, read> masks: array<u32>;
@group(0) @binding(9) var<storage, read> weights: array<f32>;

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
