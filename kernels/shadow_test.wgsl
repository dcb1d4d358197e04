// shadow_test: each newly rendered map is tested once per pixel; the result is cached as bit k of
// the pixel's lattice mask, so counting (reproject_count) and shading read bits, not textures.
//  gather, main (scope = global): every pixel x the listed samples.
//  list, probes (scope = local): only the samples a pixel consults, each (pixel, sample) once per
//  frame: an item's four quad corners, a probe's five new samples.

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

// ---- scope = global ----
// A sample read from a storage buffer at a per-invocation index is gathered lane by lane and
// component by component on a CPU device; read from a uniform buffer it is loaded once per SIMD
// row. So `gather` copies the requested samples of the test list into one uniform list, and `main`
// loops over it. (A loop over the uniform list measured faster on llvmpipe than unrolled blocks of
// 16, one dispatch each: docs/bench.md.)
struct GpuTestList {
    count: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    // In list order; `lattice` is the sample's lattice index k (gather sets it).
    samples: array<GpuSample, LATTICE_POINTS>,
}

@group(0) @binding(18) var<uniform> test_samples: GpuTestList;
@group(0) @binding(19) var<storage, read_write> gathered: GpuTestList;

// One invocation: the list is at most LATTICE_POINTS long and keeps its order.
@compute @workgroup_size(1, 1, 1)
fn gather() {
    let listed = select(level.work_count, control_words[1], level.requested == 1u);
    var m = 0u;
    for (var t = 0u; t < listed; t = t + 1u) {
        let k = test_list[t];
        if (lattice_state[k] == 0u) {
            continue;
        }
        var s = samples[k];
        s.lattice = k;
        gathered.samples[m] = s;
        m = m + 1u;
    }
    gathered.count = m;
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
    let normal = textureLoad(gbuffer_normal, pixel, 0).xyz;
    let base = (gid.y * frame.width + gid.x) * MASK_WORDS;
    // The list keeps the test list's order (sorted in the waiting loop), so its bits arrive word by
    // word: one running word in a register (a dynamically indexed local array spills to memory on
    // CPU devices), written when it changes.
    var word = MASK_WORDS;
    var bits = 0u;
    var summary = SUMMARY_GEOMETRY;
    for (var t = 0u; t < test_samples.count; t = t + 1u) {
        let s = test_samples.samples[t];
        let k = s.lattice;
        if (k / 32u != word) {
            if (word < MASK_WORDS && bits != 0u) {
                masks[base + word] = masks[base + word] | bits;
            }
            word = k / 32u;
            bits = 0u;
        }
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

// ---- scope = local ----
// A pixel's (pixel, sample) pairs are claimed in `consulted` (same layout as the masks): the one
// invocation whose atomicOr set the bit looks the sample up and ORs the lit bit into the mask. Pixels
// of a split quad's four children share 9 samples among 16 corners, and a level's corners include
// its parents', so most claims find the bit set and cost no lookup. The next dispatch
// (reproject_count `list`, probe) reads the bits.
@group(0) @binding(10) var<storage, read_write> consulted: array<atomic<u32>>;
@group(0) @binding(11) var<storage, read_write> lattice_lit: array<atomic<u32>>;
// Every map stays alive under local scope, in up to two arrays (GpuSample.array).
@group(0) @binding(12) var maps_a: texture_depth_2d_array;
@group(0) @binding(13) var maps_b: texture_depth_2d_array;
// The level's items (pixel, quad) or probes (pixel, first child | PROBE_LIT), and their count.
@group(0) @binding(14) var<storage, read> work: array<vec2<u32>>;
@group(0) @binding(15) var<storage, read> work_total: array<u32>;
@group(0) @binding(16) var<storage, read> quads: array<GpuQuad>;
@group(0) @binding(17) var<storage, read_write> control: GpuControl;

var<workgroup> group_lookups: atomic<u32>;

// Claims up to 5 samples `ks` (n of them) of pixel p and tests those this invocation claimed;
// returns the number of lookups.
fn test_claimed(p: u32, ks: array<u32, 5>, n: u32) -> u32 {
    var mine = 0u;
    for (var i = 0u; i < n; i = i + 1u) {
        let k = ks[i];
        let bit = 1u << (k % 32u);
        if ((atomicOr(&consulted[p * MASK_WORDS + k / 32u], bit) & bit) == 0u) {
            mine = mine | (1u << i);
        }
    }
    if (mine == 0u) {
        return 0u;
    }
    let pixel = vec2<i32>(i32(p % frame.width), i32(p / frame.width));
    let position = textureLoad(gbuffer_position, pixel, 0).xyz;
    let normal = textureLoad(gbuffer_normal, pixel, 0).xyz;
    for (var i = 0u; i < n; i = i + 1u) {
        if ((mine & (1u << i)) == 0u) {
            continue;
        }
        let k = ks[i];
        let s = samples[k];
        let lookup = shadow_lookup(frame, s, position, normal);
        var stored: f32;
        if (s.array == 0u) {
            stored = textureLoad(maps_a, lookup.texel, i32(s.layer), 0);
        } else {
            stored = textureLoad(maps_b, lookup.texel, i32(s.layer), 0);
        }
        if (shadow_compare(s, lookup, stored) == 1u) {
            atomicOr(&lattice_lit[p * MASK_WORDS + k / 32u], 1u << (k % 32u));
        }
    }
    return countOneBits(mine);
}

// One global atomic per workgroup for the level's lookup count (a test compares it with the twin).
fn add_lookups(n: u32, lid: u32) {
    if (n != 0u) {
        atomicAdd(&group_lookups, n);
    }
    workgroupBarrier();
    if (lid == 0u) {
        let total = atomicLoad(&group_lookups);
        if (total != 0u) {
            atomicAdd(&control.lookups, total);
        }
    }
}

// One item each: the four corners of its quad.
@compute @workgroup_size(64, 1, 1)
fn list(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    var n = 0u;
    if (gid.x < work_total[0]) {
        let item = work[gid.x];
        let q = quads[item.y];
        let ks = array<u32, 5>(quad_corner(q, 0u), quad_corner(q, 1u), quad_corner(q, 2u), quad_corner(q, 3u), 0u);
        n = test_claimed(item.x, ks, 4u);
    }
    add_lookups(n, lid);
}

// One probe each: its parent's five new samples.
@compute @workgroup_size(64, 1, 1)
fn probes(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    var n = 0u;
    if (gid.x < work_total[0]) {
        let probe = work[gid.x];
        let q = quads[probe.y & ~PROBE_LIT];
        let ks = array<u32, 5>(probe_point(q, 0u), probe_point(q, 1u), probe_point(q, 2u), probe_point(q, 3u), probe_point(q, 4u));
        n = test_claimed(probe.x, ks, 5u);
    }
    add_lookups(n, lid);
}
