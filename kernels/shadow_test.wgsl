// shadow_test: each newly rendered map is tested once per pixel; the result is cached as bit k of
// the pixel's lattice mask, so counting (reproject_count) and shading read bits, not textures.

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> level: GpuLevel;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var<storage, read> test_list: array<u32>;
@group(0) @binding(4) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(5) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(6) var shadow_maps: ShadowMaps;
@group(0) @binding(7) var<storage, read_write> masks: array<u32>;
// Listed samples not requested (0) have no map this frame: the GPU-steered loop lists every
// candidate of a level and skips those subdivide did not request.
@group(0) @binding(8) var<storage, read> lattice_state: array<u32>;
// GpuControl's words; word 1 counts the samples subdivide requested (level.requested = 1).
@group(0) @binding(9) var<storage, read> control_words: array<u32>;

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
    let base = (gid.y * frame.width + gid.x) * MASK_WORDS;
    // The test list is sorted, so its bits arrive word by word: one running word in a register
    // (a dynamically indexed local array spills to memory on CPU devices), written when it changes.
    var word = MASK_WORDS;
    var bits = 0u;
    var summary = SUMMARY_GEOMETRY;
    let count = select(level.work_count, control_words[1], level.requested == 1u);
    for (var t = 0u; t < count; t = t + 1u) {
        let k = test_list[t];
        if (k / 32u != word) {
            if (word < MASK_WORDS && bits != 0u) {
                masks[base + word] = masks[base + word] | bits;
            }
            word = k / 32u;
            bits = 0u;
        }
        if (lattice_state[k] == 0u) {
            continue;
        }
        let s = samples[k];
        let lookup = shadow_lookup(frame, s, position.xyz, normal);
        let stored = map_depth(frame, shadow_maps, s, lookup.texel);
        let lit = shadow_compare(s, lookup, stored);
        bits = bits | (lit << (k % 32u));
        summary = summary | select(SUMMARY_ANY_UNLIT, SUMMARY_ANY_LIT, lit == 1u);
    }
    if (word == SUMMARY_WORD) {
        bits = bits | summary;
    } else {
        masks[base + SUMMARY_WORD] = masks[base + SUMMARY_WORD] | summary;
    }
    if (word < MASK_WORDS && bits != 0u) {
        masks[base + word] = masks[base + word] | bits;
    }
}
