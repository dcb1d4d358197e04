// shadow_test: each newly rendered map is tested once per pixel; the result is cached as bit k of
// the pixel's lattice mask, so counting (reproject_count) and shading read bits, not textures.
//  fill_blocks, block16 .. block1 (scope = global): every pixel x the listed samples.
//  list, probes (scope = local): only the samples a pixel consults, each (pixel, sample) once per
//  frame: an item's four quad corners, a probe's five new samples.

@group(0) @binding(0) var<uniform> frame: GpuFrame;
// work_count: the test list's length, or with requested = 1 the most it can hold (the block slots).
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

// ---- scope = global: the listed samples in uniform blocks ----
// A sample read from a storage buffer at a per-invocation index is gathered lane by lane and
// component by component on a CPU device; read from a uniform buffer at a constant offset it is
// loaded once per SIMD row, but only where no lane mask is open (no early return, loop or `if`
// around the read; docs/gpu-frame.md §4). So `fill_blocks` copies the requested samples of the
// list into blocks of a uniform buffer, and one dispatch per block tests them, unrolled, for every
// pixel of the dispatch: only the stores are conditional. llvmpipe runs every line of an unrolled
// block, so a block is exactly full: slots of TEST_BLOCK, then one each of 8, 4, 2 and 1 samples.
// Rust's TEST_BLOCK, TEST_SLOTS and TEST_BLOCK_BYTES (src/stages/shadow_test.rs) are these numbers.
const TEST_BLOCK: u32 = 16u;
const TEST_TAILS: u32 = 4u;
const TEST_SLOTS: u32 = 22u;
// 2048 bytes: slots at 256-byte-aligned offsets of one buffer.
struct GpuTestBlock {
    // Lattice index of the block's sample j: ks[j / 4][j % 4] (uniform arrays have a 16-byte stride).
    ks: array<vec4<u32>, 4>,
    samples: array<GpuSample, TEST_BLOCK>,
    pad: array<vec4<u32>, 12>,
}

// The dispatched slot's block (a 2048-byte range of `blocks`).
@group(0) @binding(18) var<uniform> block: GpuTestBlock;
@group(0) @binding(19) var<storage, read_write> blocks: array<GpuTestBlock, TEST_SLOTS>;
// Slot s's dispatch_workgroups_indirect arguments at words 3s .. 3s + 2 (x = 0: nothing to test):
// one workgroup per geometry tile of the frame's list (kernels/shared/common.wgsl).
@group(0) @binding(20) var<storage, read_write> block_args: array<u32>;
@group(0) @binding(21) var<storage, read> tile_list: array<u32>;

// Slot of the requested sample i of m (in list order) and its place in the slot: the full blocks
// first, then the tails of m % TEST_BLOCK, largest first.
fn block_place(i: u32, m: u32) -> vec2<u32> {
    let full = m / TEST_BLOCK;
    if (i < full * TEST_BLOCK) {
        return vec2<u32>(i / TEST_BLOCK, i % TEST_BLOCK);
    }
    var o = i - full * TEST_BLOCK;
    let rest = m % TEST_BLOCK;
    let slots = level.work_count / TEST_BLOCK;
    for (var n = 0u; n < TEST_TAILS; n = n + 1u) {
        let size = (TEST_BLOCK / 2u) >> n;
        if ((rest & size) != 0u) {
            if (o < size) {
                return vec2<u32>(slots + n, o);
            }
            o = o - size;
        }
    }
    // Not reached: the tails hold exactly m % TEST_BLOCK samples.
    return vec2<u32>(TEST_SLOTS, 0u);
}

// One invocation: the list is at most LATTICE_POINTS long, and the order of the copies is fixed.
@compute @workgroup_size(1, 1, 1)
fn fill_blocks() {
    let listed = select(level.work_count, control_words[1], level.requested == 1u);
    var m = 0u;
    for (var t = 0u; t < listed; t = t + 1u) {
        m = m + select(0u, 1u, lattice_state[test_list[t]] != 0u);
    }
    var i = 0u;
    for (var t = 0u; t < listed; t = t + 1u) {
        let k = test_list[t];
        if (lattice_state[k] == 0u) {
            continue;
        }
        let at = block_place(i, m);
        blocks[at.x].ks[at.y / 4u][at.y % 4u] = k;
        blocks[at.x].samples[at.y] = samples[k];
        i = i + 1u;
    }
    // Every slot the host may dispatch: the full blocks of the longest list, then the tails.
    let tiles = tile_list[0];
    let slots = level.work_count / TEST_BLOCK;
    let full = m / TEST_BLOCK;
    let rest = m % TEST_BLOCK;
    for (var s = 0u; s < slots + TEST_TAILS; s = s + 1u) {
        var used = s < full;
        if (s >= slots) {
            used = (rest & ((TEST_BLOCK / 2u) >> (s - slots))) != 0u;
        }
        block_args[3u * s] = select(0u, tiles, used);
        block_args[3u * s + 1u] = 1u;
        block_args[3u * s + 2u] = 1u;
    }
}

// A pixel's running mask word: a block's samples keep the list's order (sorted in the waiting loop),
// so its bits arrive word by word and one word stays in a register (a dynamically indexed local
// array spills to memory on CPU devices), ORed into the mask when the word changes.
struct Running {
    base: u32,
    word: u32,
    bits: u32,
    summary: u32,
    // Inside the image and on geometry: the pixel's words are written.
    geometry: bool,
}

fn flush_word(r: Running) {
    if (r.geometry && r.word < MASK_WORDS && r.bits != 0u) {
        masks[r.base + r.word] = masks[r.base + r.word] | r.bits;
    }
}

// The block's sample j tested at p (normal n): its lit bit joins the running word. The reads come
// first, outside the flush's `if`.
// `cube` (a constant in each entry point: the cube* entries; the branch, even never taken, made the
// block entries twice as slow on a CPU device): a point light's lattice sample is six cube faces,
// face f's record at samples[k + 289 f] (the block holds face 0's), and p is tested on the face
// that holds its direction.
fn test_sample(r: Running, j: u32, p: vec3<f32>, n: vec3<f32>, cube: bool) -> Running {
    var out = r;
    let k = block.ks[j / 4u][j % 4u];
    var s = block.samples[j];
    if (cube) {
        s = samples[k + LATTICE_POINTS * face_offset(frame, s, p)];
    }
    let lookup = shadow_lookup(frame, s, p, n);
    let stored = map_depth(frame, shadow_maps, s, lookup.texel);
    let lit = shadow_compare(s, lookup, stored);
    if (k / 32u != out.word) {
        flush_word(out);
    }
    out.bits = select(out.bits, 0u, k / 32u != out.word) | (lit << (k % 32u));
    out.word = k / 32u;
    out.summary = out.summary | select(SUMMARY_ANY_UNLIT, SUMMARY_ANY_LIT, lit == 1u);
    return out;
}

// The pixel's G-buffer point; outside the image the edge pixel's, never written.
struct BlockPixel {
    position: vec4<f32>,
    normal: vec3<f32>,
    running: Running,
}

fn block_pixel(gid: vec3<u32>) -> BlockPixel {
    var out: BlockPixel;
    let inside = gid.x < frame.width && gid.y < frame.height;
    let pixel = vec2<i32>(min(gid.xy, vec2<u32>(frame.width - 1u, frame.height - 1u)));
    out.position = textureLoad(gbuffer_position, pixel, 0);
    out.normal = textureLoad(gbuffer_normal, pixel, 0).xyz;
    out.running = Running((gid.y * frame.width + gid.x - band_base(frame)) * MASK_WORDS, MASK_WORDS, 0u, SUMMARY_GEOMETRY, inside && out.position.w != 0.0);
    return out;
}

// The last running word and the summary flags (in word SUMMARY_WORD, above the lattice's bits).
fn finish_block(r: Running) {
    if (!r.geometry) {
        return;
    }
    var last = r;
    if (last.word == SUMMARY_WORD) {
        last.bits = last.bits | last.summary;
    } else {
        masks[last.base + SUMMARY_WORD] = masks[last.base + SUMMARY_WORD] | last.summary;
    }
    flush_word(last);
}

@compute @workgroup_size(8, 8, 1)
fn block16(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let px = block_pixel(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width));
    let p = px.position.xyz;
    var r = px.running;
    r = test_sample(r, 0u, p, px.normal, false);
    r = test_sample(r, 1u, p, px.normal, false);
    r = test_sample(r, 2u, p, px.normal, false);
    r = test_sample(r, 3u, p, px.normal, false);
    r = test_sample(r, 4u, p, px.normal, false);
    r = test_sample(r, 5u, p, px.normal, false);
    r = test_sample(r, 6u, p, px.normal, false);
    r = test_sample(r, 7u, p, px.normal, false);
    r = test_sample(r, 8u, p, px.normal, false);
    r = test_sample(r, 9u, p, px.normal, false);
    r = test_sample(r, 10u, p, px.normal, false);
    r = test_sample(r, 11u, p, px.normal, false);
    r = test_sample(r, 12u, p, px.normal, false);
    r = test_sample(r, 13u, p, px.normal, false);
    r = test_sample(r, 14u, p, px.normal, false);
    r = test_sample(r, 15u, p, px.normal, false);
    finish_block(r);
}

@compute @workgroup_size(8, 8, 1)
fn block8(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let px = block_pixel(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width));
    let p = px.position.xyz;
    var r = px.running;
    r = test_sample(r, 0u, p, px.normal, false);
    r = test_sample(r, 1u, p, px.normal, false);
    r = test_sample(r, 2u, p, px.normal, false);
    r = test_sample(r, 3u, p, px.normal, false);
    r = test_sample(r, 4u, p, px.normal, false);
    r = test_sample(r, 5u, p, px.normal, false);
    r = test_sample(r, 6u, p, px.normal, false);
    r = test_sample(r, 7u, p, px.normal, false);
    finish_block(r);
}

@compute @workgroup_size(8, 8, 1)
fn block4(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let px = block_pixel(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width));
    let p = px.position.xyz;
    var r = px.running;
    r = test_sample(r, 0u, p, px.normal, false);
    r = test_sample(r, 1u, p, px.normal, false);
    r = test_sample(r, 2u, p, px.normal, false);
    r = test_sample(r, 3u, p, px.normal, false);
    finish_block(r);
}

@compute @workgroup_size(8, 8, 1)
fn block2(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let px = block_pixel(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width));
    let p = px.position.xyz;
    var r = px.running;
    r = test_sample(r, 0u, p, px.normal, false);
    r = test_sample(r, 1u, p, px.normal, false);
    finish_block(r);
}

@compute @workgroup_size(8, 8, 1)
fn block1(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let px = block_pixel(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width));
    var r = px.running;
    r = test_sample(r, 0u, px.position.xyz, px.normal, false);
    finish_block(r);
}

// The blocks for a point light's cube maps (`test_sample`'s `cube`): the first `count` samples of
// the block.
fn cube_block(group: vec3<u32>, lid: vec3<u32>, count: u32) {
    let px = block_pixel(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width));
    var r = px.running;
    for (var j = 0u; j < count; j = j + 1u) {
        r = test_sample(r, j, px.position.xyz, px.normal, true);
    }
    finish_block(r);
}

@compute @workgroup_size(8, 8, 1)
fn cube16(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    cube_block(group, lid, 16u);
}

@compute @workgroup_size(8, 8, 1)
fn cube8(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    cube_block(group, lid, 8u);
}

@compute @workgroup_size(8, 8, 1)
fn cube4(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    cube_block(group, lid, 4u);
}

@compute @workgroup_size(8, 8, 1)
fn cube2(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    cube_block(group, lid, 2u);
}

@compute @workgroup_size(8, 8, 1)
fn cube1(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    cube_block(group, lid, 1u);
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
@group(0) @binding(12) var maps_a: ShadowMaps;
@group(0) @binding(13) var maps_b: ShadowMaps;
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
            stored = map_depth(frame, maps_a, s, lookup.texel);
        } else {
            stored = map_depth(frame, maps_b, s, lookup.texel);
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
    if (list_index(gid) < work_total[0]) {
        let item = work[list_index(gid)];
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
    if (list_index(gid) < work_total[0]) {
        let probe = work[list_index(gid)];
        let q = quads[probe.y & ~PROBE_LIT];
        let ks = array<u32, 5>(probe_point(q, 0u), probe_point(q, 1u), probe_point(q, 2u), probe_point(q, 3u), probe_point(q, 4u));
        n = test_claimed(probe.x, ks, 5u);
    }
    add_lookups(n, lid);
}
