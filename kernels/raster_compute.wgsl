// raster_compute: a depth-only shadow-map raster in compute kernels, many maps per dispatch, with
// exact rules (docs/gpu-frame.md §7) that the CPU twin (src/stages/twin/raster_compute.rs) repeats
// bit for bit:
// - vertices are projected with the sample's matrix and snapped to 1/256 texel (16.8 fixed point);
// - a texel is covered when its centre is inside the snapped triangle by integer edge functions,
//   with the top-left rule on ties, so a shared edge covers each texel once;
// - its depth is the triangle's plane at the centre, from the integer edge values as weights;
// - depths go into one u32 per texel (the bits of a non-negative f32 order like the values) by
//   atomicMin, over a buffer cleared to the far value 1.0.
// Edge values need 49 bits: they are two-word integers (`Wide`), exact, as i64 on the CPU.
// Every f32 product that feeds an addition goes through `fence`, so no compiler can fuse it into an
// fma and round it differently from the twin.
// Under the GPU-steered loop (`requested`), the chain's jobs and the dispatch sizes of `clear`, `main_maps`
// and `store` come from subdivide's request list, so only the maps a level asked for are cleared,
// rasterized and stored, and nothing waits.
// Work items are (triangle, map) pairs. `main_maps` takes a triangle per invocation and loops over
// the chain's maps, so its vertices are read once per chain, not once per map (`main`, a pair per
// invocation, serves kept lists, which differ from map to map). Each pair of a run facing away
// (the scene's cull mode) is dropped; the others are set up and rejected when their box holds no
// texel centre; a small one (box at most RASTER_SMALL_SIDE² texels) is rasterized in its
// invocation, a large one is queued for `large_tiles` as one entry per block of RASTER_TILE_BLOCK
// tiles of RASTER_LARGE_TILE² texels, a workgroup per entry. A pair over a whole map queues many
// entries, the rest one each: the dispatch is as long as the entries, where a dispatch of every
// pair times the largest pair's blocks ran 25 M mostly idle workgroups for a 2048² map's ground
// plane beside a mesh's 800 k large pairs (22 s against 1.5 s for the fixed-function raster on
// lavapipe).

struct GpuRasterCompute {
    map_size: u32,
    triangle_count: u32,
    // 0: no face is skipped; 1: back faces; 2: front faces (as the fixed-function raster culls).
    cull_face: u32,
    // Maps in this dispatch chain (the rows of `jobs` and of `depth`).
    map_count: u32,
    // Pairs `large` can hold; beyond it `main_maps` or `main` rasterizes a large triangle itself.
    large_capacity: u32,
    // Always 0: XORed into a product's bits, which hides the product from the compiler's fma fusion.
    fence: u32,
    // `requested`: the first request of this chain (its index in the level's request list).
    first_request: u32,
    // 1 under the GPU-steered loop: the chain's maps are its share of the requests (`chain_maps`).
    steered: u32,
}

// One map of the chain: its sample and the texel rectangle [first, last] (inclusive) it is
// rasterized in. Texels outside keep the far value, as outside a fixed-function scissor.
struct GpuRasterJob {
    sample: u32,
    first_x: u32,
    first_y: u32,
    last_x: u32,
    last_y: u32,
    // The cull pass's slot whose kept triangles the map draws (`indices` is then the pass's kept
    // lists, a slot per whole mesh, and `kept_counts` its draw arguments), or RASTER_WHOLE_MESH.
    kept_slot: u32,
    pad1: u32,
    pad2: u32,
}

// f32 words per vertex (scene::Vertex: position, normal, material); the position comes first.
// Sub-texel bits of the snapped vertices.
const RASTER_SUBTEXEL_BITS: u32 = 8u;
// Largest |coordinate| of a snapped vertex, in 1/256 texels: 2^23 (32768 texels). Edge values stay
// below 2^49 and steps below 2^32 in magnitude.
const RASTER_COORD_LIMIT: f32 = 8388608.0;
// A triangle whose box is at most this many texel centres on each side is small.
const RASTER_SMALL_SIDE: i32 = 4;
// Side of `large`'s tiles, in texels.
const RASTER_LARGE_TILE: i32 = 8;
// Tiles one workgroup of `large_tiles` takes of a queued pair (32 per invocation): a CPU device
// (lavapipe) stops a shader's loops after 65,535 iterations in all, and a pair over a whole 2048²
// map is 65,536 tiles, so a pair's tiles are spread over as many workgroups as its blocks.
const RASTER_TILE_BLOCK: i32 = 2048;
// Words each invocation of `clear` sets, 64 apart: a CPU device (lavapipe) pays a fixed cost per
// workgroup that one-word invocations spend most of their time in.
const RASTER_CLEAR_RUN: u32 = 16u;
// A queued entry that holds no block: the rest of a pair's reservation past the queue's end (the
// pair is rasterized by its own invocation instead).
const RASTER_NO_ENTRY: u32 = 0xffffffffu;
// An entry's first word: the map in the low 16 bits (a chain holds at most 65,535 maps: the
// dispatch's row limit), the block of the pair's tiles in the high 16 (at most 512 for 8192²).
const RASTER_MAP_BITS: u32 = 16u;
// GpuRasterJob.kept_slot of a map that draws the whole mesh.
const RASTER_WHOLE_MESH: u32 = 0xffffffffu;
// u32 words per slot of `kept_counts` (draw_indexed_indirect arguments: the index count first).
const RASTER_KEPT_ARGS: u32 = 5u;
// Triangles per run of `runs` (the cull pass's CULL_RUN).
const RASTER_RUN: u32 = 32u;
// The stored word of the far value, 1.0.
const RASTER_FAR: u32 = 0x3f800000u;

@group(0) @binding(0) var<uniform> params: GpuRasterCompute;
@group(0) @binding(1) var<storage, read> samples: array<GpuSample>;
// Each map of the chain (written by `requested` under the GPU-steered loop).
@group(0) @binding(2) var<storage, read_write> jobs: array<GpuRasterJob>;
// Vertex positions, one vec4 each (w unused): one load per vertex where the scene's interleaved
// vertices take three bounds-checked word loads on a CPU device (about a tenth of the stage on
// bunny-seed-framing; packing each triangle's indices into a vec4 as well gained nothing more).
@group(0) @binding(3) var<storage, read> positions: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> indices: array<u32>;
// map_count maps of map_size² words, row-major, row 0 at the top (NDC y = 1).
@group(0) @binding(5) var<storage, read_write> depth: array<atomic<u32>>;
// Queued large pairs' blocks: (map | block << RASTER_MAP_BITS, triangle).
@group(0) @binding(6) var<storage, read_write> large: array<u32>;
// [pairs queued, the most tiles of one queued pair past RASTER_TILE_BLOCK (else 0)].
@group(0) @binding(7) var<storage, read_write> control: array<atomic<u32>>;
// `large`'s indirect dispatch (x, y, z).
@group(0) @binding(8) var<storage, read_write> dispatch: array<u32>;
// `requested`: the level's request count (GpuControl.new_sample_count, word 1) and list (subdivide's
// new_samples); what it writes: the chain's map count, then the indirect dispatches of `clear`,
// `main_maps` and `store`, three words each (STEER_ARGS_* word offsets).
@group(0) @binding(9) var<storage, read> request_control: array<u32>;
@group(0) @binding(10) var<storage, read> request_list: array<u32>;
@group(0) @binding(11) var<storage, read_write> steer_args: array<u32>;
// Per run of RASTER_RUN triangles of the shadow order: box and normal cone (faces_away).
@group(0) @binding(14) var<storage, read> runs: array<vec4<f32>>;
// The cull pass's draw arguments, RASTER_KEPT_ARGS words per slot (maps with a kept_slot).
@group(0) @binding(15) var<storage, read> kept_counts: array<u32>;
// `store`: the method's R32Uint layers; map m goes to its sample's layer.
@group(0) @binding(12) var layers: texture_storage_2d_array<r32uint, write>;
@group(0) @binding(13) var<storage, read> layer_samples: array<GpuSample>;

const STEER_ARGS_CLEAR: u32 = 1u;
const STEER_ARGS_MAIN: u32 = 4u;
const STEER_ARGS_STORE: u32 = 7u;

fn fence(x: f32) -> f32 {
    return bitcast<f32>(bitcast<u32>(x) ^ params.fence);
}

// A two's-complement 64-bit integer: (low word, high word).
alias Wide = vec2<u32>;

fn wide_add(a: Wide, b: Wide) -> Wide {
    let lo = a.x + b.x;
    return Wide(lo, a.y + b.y + select(0u, 1u, lo < a.x));
}

fn wide_neg(a: Wide) -> Wide {
    let lo = ~a.x + 1u;
    return Wide(lo, ~a.y + select(0u, 1u, lo == 0u));
}

// a · b exactly, from four 16 × 16-bit products of the magnitudes.
fn wide_mul(a: i32, b: i32) -> Wide {
    let ua = u32(abs(a));
    let ub = u32(abs(b));
    let a0 = ua & 0xffffu;
    let a1 = ua >> 16u;
    let b0 = ub & 0xffffu;
    let b1 = ub >> 16u;
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let mid = p01 + a1 * b0;
    let mid_carry = select(0u, 0x10000u, mid < p01);
    let lo = p00 + (mid << 16u);
    let hi = a1 * b1 + (mid >> 16u) + mid_carry + select(0u, 1u, lo < p00);
    let m = Wide(lo, hi);
    return select(m, wide_neg(m), (a < 0) != (b < 0));
}

// The nearest f32: the high word exactly (|value| < 2^49), scaled by 2^32 exactly, plus the low word rounded.
fn wide_f32(a: Wide) -> f32 {
    return f32(bitcast<i32>(a.y)) * 4294967296.0 + f32(a.x);
}

// value > 0, or value = 0 on a top-left edge.
fn edge_covers(e: Wide, top_left: bool) -> bool {
    let negative = bitcast<i32>(e.y) < 0;
    let zero = e.x == 0u && e.y == 0u;
    return !negative && (!zero || top_left);
}

// (m · (p, 1)) with each product fenced and the sums in a fixed order.
fn project(m: mat4x4<f32>, p: vec3<f32>) -> vec4<f32> {
    var c: vec4<f32>;
    for (var r = 0; r < 4; r = r + 1) {
        c[r] = ((fence(m[0][r] * p.x) + fence(m[1][r] * p.y)) + fence(m[2][r] * p.z)) + m[3][r];
    }
    return c;
}

// A triangle set up for one map: snapped vertices (positive area in texel space, y down), their
// depths, its texel box (inclusive), and the reciprocal of its area.
struct Tri {
    v0: vec2<i32>,
    v1: vec2<i32>,
    v2: vec2<i32>,
    z: vec3<f32>,
    lo: vec2<i32>,
    hi: vec2<i32>,
    inv_area: f32,
    ok: bool,
}

// Where the job's triangles start in `indices`: a kept list is one whole-mesh slot of the cull
// pass's buffer.
fn first_index(job: GpuRasterJob) -> u32 {
    return select(job.kept_slot * params.triangle_count * 3u, 0u, job.kept_slot == RASTER_WHOLE_MESH);
}

// The job's triangle count: the whole mesh, or what the cull pass kept.
fn job_triangles(job: GpuRasterJob) -> u32 {
    if (job.kept_slot == RASTER_WHOLE_MESH) {
        return params.triangle_count;
    }
    return kept_counts[job.kept_slot * RASTER_KEPT_ARGS] / 3u;
}

// A vertex projected and snapped for one map; ok is false where w <= 0 or it lies past the limit.
struct Snapped {
    v: vec2<i32>,
    z: f32,
    ok: bool,
}

fn snap(m: mat4x4<f32>, p: vec3<f32>, scale: f32) -> Snapped {
    var s = Snapped(vec2<i32>(0), 0.0, false);
    let c = project(m, p);
    if (!(c.w > 0.0)) {
        return s;
    }
    let rw = 1.0 / c.w;
    let f = vec2<f32>(((c.x + c.w) * rw) * scale, ((c.w - c.y) * rw) * scale);
    if (!(abs(f.x) <= RASTER_COORD_LIMIT && abs(f.y) <= RASTER_COORD_LIMIT)) {
        return s;
    }
    s.v = vec2<i32>(round(f));
    s.z = c.z * rw;
    s.ok = true;
    return s;
}

// The triangle of pair (t, job): its three vertices read, then set up.
fn setup(job: GpuRasterJob, t: u32) -> Tri {
    let at = first_index(job) + t * 3u;
    return setup_points(job, positions[indices[at]].xyz, positions[indices[at + 1u]].xyz, positions[indices[at + 2u]].xyz);
}

// The triangle p0 p1 p2 set up for the job's map.
fn setup_points(job: GpuRasterJob, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>) -> Tri {
    let m = samples[job.sample].light_from_world;
    let scale = f32(params.map_size) * 128.0;
    var tri: Tri;
    tri.ok = false;
    let s0 = snap(m, p0, scale);
    let s1 = snap(m, p1, scale);
    let s2 = snap(m, p2, scale);
    if (!(s0.ok && s1.ok && s2.ok)) {
        return tri;
    }
    let v = array<vec2<i32>, 3>(s0.v, s1.v, s2.v);
    let z = vec3<f32>(s0.z, s1.z, s2.z);
    // Texel i's centre is at 256 i + 128: the first centre at or after lo, the last at or before
    // hi, inside the job's rectangle. Most triangles of a fine mesh hold none and leave here,
    // before any wide product.
    let first = vec2<i32>(i32(job.first_x), i32(job.first_y));
    let last = vec2<i32>(i32(job.last_x), i32(job.last_y));
    tri.lo = max((min(min(v[0], v[1]), v[2]) + 127) >> vec2<u32>(RASTER_SUBTEXEL_BITS), first);
    tri.hi = min((max(max(v[0], v[1]), v[2]) - 128) >> vec2<u32>(RASTER_SUBTEXEL_BITS), last);
    if (tri.lo.x > tri.hi.x || tri.lo.y > tri.hi.y) {
        return tri;
    }
    let area = wide_add(wide_mul(v[1].x - v[0].x, v[2].y - v[0].y), wide_neg(wide_mul(v[1].y - v[0].y, v[2].x - v[0].x)));
    let zero = area.x == 0u && area.y == 0u;
    // Texel space has y down: a face counter-clockwise in NDC (wgpu's front face) has negative area.
    let front = bitcast<i32>(area.y) < 0;
    if (zero || (params.cull_face == 1u && !front) || (params.cull_face == 2u && front)) {
        return tri;
    }
    tri.v0 = v[0];
    tri.v1 = select(v[1], v[2], vec2<bool>(front));
    tri.v2 = select(v[2], v[1], vec2<bool>(front));
    tri.z = select(z, z.xzy, vec3<bool>(front));
    tri.inv_area = 1.0 / wide_f32(select(area, wide_neg(area), front));
    tri.ok = true;
    return tri;
}

struct Edge {
    value: Wide,
    step_x: Wide,
    step_y: Wide,
    top_left: bool,
}

// The edge a → b at texel centre p (1/256 texels): positive inside, the weight of the third vertex.
fn edge(a: vec2<i32>, b: vec2<i32>, p: vec2<i32>) -> Edge {
    let d = b - a;
    var e: Edge;
    e.value = wide_add(wide_mul(d.x, p.y - a.y), wide_neg(wide_mul(d.y, p.x - a.x)));
    e.step_x = wide_mul(d.y, -256);
    e.step_y = wide_mul(d.x, 256);
    e.top_left = d.y < 0 || (d.y == 0 && d.x > 0);
    return e;
}

fn depth_at(e0: Wide, e1: Wide, e2: Wide, tri: Tri) -> f32 {
    let sum = fence(wide_f32(e0) * tri.z.x) + fence(wide_f32(e1) * tri.z.y);
    return (sum + fence(wide_f32(e2) * tri.z.z)) * tri.inv_area;
}

// Every texel of [lo, hi] (inclusive) that the triangle covers.
fn raster_rect(map: u32, tri: Tri, lo: vec2<i32>, hi: vec2<i32>) {
    let p = lo * 256 + 128;
    let a = edge(tri.v1, tri.v2, p);
    let b = edge(tri.v2, tri.v0, p);
    let c = edge(tri.v0, tri.v1, p);
    var row = array<Wide, 3>(a.value, b.value, c.value);
    let base = map * params.map_size * params.map_size;
    for (var y = lo.y; y <= hi.y; y = y + 1) {
        var e0 = row[0];
        var e1 = row[1];
        var e2 = row[2];
        for (var x = lo.x; x <= hi.x; x = x + 1) {
            if (edge_covers(e0, a.top_left) && edge_covers(e1, b.top_left) && edge_covers(e2, c.top_left)) {
                let d = depth_at(e0, e1, e2, tri);
                if (d >= 0.0 && d < 1.0) {
                    // The load skips the atomic where the word is already as near: the same minimum.
                    let word = bitcast<u32>(d) & 0x7fffffffu;
                    let i = base + u32(y) * params.map_size + u32(x);
                    if (word < atomicLoad(&depth[i])) {
                        atomicMin(&depth[i], word);
                    }
                }
            }
            e0 = wide_add(e0, a.step_x);
            e1 = wide_add(e1, b.step_x);
            e2 = wide_add(e2, c.step_x);
        }
        row[0] = wide_add(row[0], a.step_y);
        row[1] = wide_add(row[1], b.step_y);
        row[2] = wide_add(row[2], c.step_y);
    }
}

// The chain's maps: all of them, or under the GPU-steered loop its share of the level's requests.
fn chain_maps() -> u32 {
    if (params.steered == 0u) {
        return params.map_count;
    }
    let count = request_control[1];
    return min(count - min(count, params.first_request), params.map_count);
}

// A set-up pair: a small triangle is rasterized here, a large one queued for `large_tiles`, an
// entry per block of its tiles (or rasterized here too where its blocks do not all fit the queue).
fn draw(map: u32, t: u32, tri: Tri) {
    let side = tri.hi - tri.lo + 1;
    if (side.x > RASTER_SMALL_SIDE || side.y > RASTER_SMALL_SIDE) {
        let tiles = (side + RASTER_LARGE_TILE - 1) / RASTER_LARGE_TILE;
        let blocks = u32((tiles.x * tiles.y + RASTER_TILE_BLOCK - 1) / RASTER_TILE_BLOCK);
        let slot = atomicAdd(&control[0], blocks);
        let fits = slot < params.large_capacity && blocks <= params.large_capacity - slot;
        // Every reserved slot inside the queue is written, so `large_tiles` never reads a stale one.
        for (var b = 0u; b < blocks && slot + b < params.large_capacity; b = b + 1u) {
            large[(slot + b) * 2u] = select(RASTER_NO_ENTRY, map | (b << RASTER_MAP_BITS), fits);
            large[(slot + b) * 2u + 1u] = t;
        }
        if (fits) {
            return;
        }
    }
    raster_rect(map, tri, tri.lo, tri.hi);
}

// (x, 1, z) workgroups of a 2D dispatch of n, x at most 32768 (the Rust `rows`), with y = maps.
fn dispatch_rows(at: u32, n: u32, maps: u32) {
    let x = max(min(n, 32768u), 1u);
    steer_args[at] = x;
    steer_args[at + 1u] = maps;
    steer_args[at + 2u] = (n + x - 1u) / x;
}

// One invocation: this chain's share of the level's requests (at most map_count of them, from
// first_request on), as jobs over whole maps, and the dispatches that do only those maps. A chain
// past the last request gets empty dispatches.
@compute @workgroup_size(1, 1, 1)
fn requested() {
    let maps = chain_maps();
    let last = params.map_size - 1u;
    for (var m = 0u; m < maps; m = m + 1u) {
        jobs[m] = GpuRasterJob(request_list[params.first_request + m], 0u, 0u, last, last, RASTER_WHOLE_MESH, 0u, 0u);
    }
    steer_args[0] = maps;
    let words = maps * params.map_size * params.map_size;
    dispatch_rows(STEER_ARGS_CLEAR, (words + 64u * RASTER_CLEAR_RUN - 1u) / (64u * RASTER_CLEAR_RUN), 1u);
    dispatch_rows(STEER_ARGS_MAIN, select(0u, (params.triangle_count + 63u) / 64u, maps > 0u), 1u);
    dispatch_rows(STEER_ARGS_STORE, (params.map_size * params.map_size + 63u) / 64u, maps);
}

// One invocation: `main`'s dispatch over a chain whose jobs draw kept lists, as wide as the longest
// list (written where `requested` writes it), so the pairs past every list cost no workgroup.
@compute @workgroup_size(1, 1, 1)
fn kept_extent() {
    var most = 0u;
    for (var m = 0u; m < params.map_count; m = m + 1u) {
        most = max(most, job_triangles(jobs[m]));
    }
    dispatch_rows(STEER_ARGS_MAIN, (most + 63u) / 64u, params.map_count);
}

// One invocation per (texel, map): the word into layer `layer_samples[job.sample].layer`.
@compute @workgroup_size(64, 1, 1)
fn store(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let texel = (wg.z * groups.x + wg.x) * 64u + lid;
    let map = wg.y;
    let texels = params.map_size * params.map_size;
    if (texel >= texels) {
        return;
    }
    let word = atomicLoad(&depth[map * texels + texel]);
    let layer = layer_samples[jobs[map].sample].layer;
    textureStore(layers, vec2<u32>(texel % params.map_size, texel / params.map_size), layer, vec4<u32>(word, 0u, 0u, 0u));
}

// Every word of the chain's maps to the far value: RASTER_CLEAR_RUN words per invocation, 64
// apart, a run of 64 · RASTER_CLEAR_RUN per workgroup x + z · rows.
@compute @workgroup_size(64, 1, 1)
fn clear(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let first = (wg.z * groups.x + wg.x) * 64u * RASTER_CLEAR_RUN + lid;
    let words = params.map_count * params.map_size * params.map_size;
    for (var word = first; word < min(first + 64u * RASTER_CLEAR_RUN, words); word = word + 64u) {
        atomicStore(&depth[word], RASTER_FAR);
    }
}

// One invocation per (triangle, map) of a chain whose jobs draw kept lists: the map is the workgroup
// row, the triangle x + z · rows.
@compute @workgroup_size(64, 1, 1)
fn main(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let t = (wg.z * groups.x + wg.x) * 64u + lid;
    let map = wg.y;
    let job = jobs[map];
    if (t >= job_triangles(job)) {
        return;
    }
    // A run whose every triangle faces the way the scene culls, by a margin no snap can cross, is
    // dropped before any vertex is read: about half of a closed mesh, for the price of one test
    // that the run's invocations share. (A kept list was tested so by the cull pass.)
    // A light at infinity (an orthographic map, position.w = 0) has no eye to face away from.
    let eye = samples[job.sample].position;
    if (params.cull_face != 0u && job.kept_slot == RASTER_WHOLE_MESH && eye.w == 1.0) {
        let r = t / RASTER_RUN;
        let axis = runs[r * 3u + 2u];
        let facing = select(axis, vec4<f32>(-axis.xyz, axis.w), params.cull_face == 2u);
        if (faces_away(eye.xyz, runs[r * 3u], runs[r * 3u + 1u], facing)) {
            return;
        }
    }
    let tri = setup(jobs[map], t);
    if (tri.ok) {
        draw(map, t, tri);
    }
}

// Between the passes: `large_tiles`' dispatch, a workgroup per queued entry (a pair's block of
// RASTER_TILE_BLOCK tiles), in rows of at most 32768 (x along a row, z across rows).
@compute @workgroup_size(1, 1, 1)
fn begin() {
    let queued = min(atomicLoad(&control[0]), params.large_capacity);
    let row = max(min(queued, 32768u), 1u);
    dispatch[0] = row;
    dispatch[1] = 1u;
    dispatch[2] = (queued + row - 1u) / row;
}

// A workgroup per queued entry: its invocations take the block's tiles in turn.
@compute @workgroup_size(64, 1, 1)
fn large_tiles(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let slot = wg.z * groups.x + wg.x;
    if (slot >= min(atomicLoad(&control[0]), params.large_capacity)) {
        return;
    }
    let word = large[slot * 2u];
    if (word == RASTER_NO_ENTRY) {
        return;
    }
    let map = word & ((1u << RASTER_MAP_BITS) - 1u);
    let tri = setup(jobs[map], large[slot * 2u + 1u]);
    let tiles = (tri.hi - tri.lo + RASTER_LARGE_TILE) / RASTER_LARGE_TILE;
    let first = i32(word >> RASTER_MAP_BITS) * RASTER_TILE_BLOCK;
    let end = min(first + RASTER_TILE_BLOCK, tiles.x * tiles.y);
    for (var k = first + i32(lid); k < end; k = k + 64) {
        let lo = tri.lo + vec2<i32>(k % tiles.x, k / tiles.x) * RASTER_LARGE_TILE;
        raster_rect(map, tri, lo, min(lo + RASTER_LARGE_TILE - 1, tri.hi));
    }
}

// One invocation per triangle over every map of a chain that draws the whole mesh: the vertices are
// read once for all the maps, and each pair is set up, rejected, rasterized or queued as in `main`.
@compute @workgroup_size(64, 1, 1)
fn main_maps(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let t = (wg.z * groups.x + wg.x) * 64u + lid;
    if (t >= params.triangle_count) {
        return;
    }
    let p0 = positions[indices[t * 3u]].xyz;
    let p1 = positions[indices[t * 3u + 1u]].xyz;
    let p2 = positions[indices[t * 3u + 2u]].xyz;
    let r = t / RASTER_RUN;
    let axis = runs[r * 3u + 2u];
    let facing = select(axis, vec4<f32>(-axis.xyz, axis.w), params.cull_face == 2u);
    let maps = chain_maps();
    for (var map = 0u; map < maps; map = map + 1u) {
        let job = jobs[map];
        let eye = samples[job.sample].position;
        if (params.cull_face != 0u && eye.w == 1.0 && faces_away(eye.xyz, runs[r * 3u], runs[r * 3u + 1u], facing)) {
            continue;
        }
        let tri = setup_points(job, p0, p1, p2);
        if (tri.ok) {
            draw(map, t, tri);
        }
    }
}
