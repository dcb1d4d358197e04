// cull: for each map of a batch, the triangles that can change the map at a texel its pixels test
// (scope = local: compact keeps, per lattice sample and culling tile, the largest depth limit its
// pixels compare with). The mesh is read in the shadow raster's order (Morton order of centroids),
// in runs of CULL_RUN consecutive triangles, one invocation each. A run is dropped when its normal
// cone shows every triangle facing the way the raster culls, or when its box, projected, cannot
// reach such a texel; otherwise each triangle is tested the same way with its own three vertices.
// A triangle, or box, is dropped when no texel centre within CULL_MARGIN of its projected bounds
// lies in a tile where its nearest depth could shadow a tested pixel. Most triangles of a
// finely tessellated mesh cover no texel centre at all and are dropped on that alone.
// Runs are tested first (phase 1, `main`); the triangles of the runs that pass, one invocation
// each, next (phase 2, `triangles`, dispatched indirectly by `begin`). Kept triangles are
// appended to the slot's index list, whose draw_indexed_indirect arguments this pass writes: the
// raster draws only them. A depth-only raster with a Less test keeps the nearest
// fragment whatever the order, and the test is monotone in the stored depth, so every tested
// pixel's outcome is the full raster's.

struct GpuCull {
    triangle_count: u32,
    // Index capacity of one slot (the whole mesh: no slot can overflow).
    slot_stride: u32,
    // 0: the raster culls no face; 1: back faces; 2: front faces.
    cull_face: u32,
    groups_x: u32,
}

// Texels of slack around projected bounds. A triangle writes a texel only if the texel's centre
// lies in the triangle after its vertices snap to the rasterizer's sub-texel grid: at most 1/32
// texel away (Vulkan guarantees at least 4 sub-pixel bits); this float projection and the
// raster's differ by far less than the remaining 1/32.
const CULL_MARGIN: f32 = 0.0625;
// Stored-depth slack below the least depth of a box or triangle: 256 ulps at depth 1, while the
// raster's own projection and interpolation of a vertex's depth differ from this one by a few.
const CULL_DEPTH_SLACK: f32 = 1.52587890625e-5;
// Bounds spanning more tiles than this are kept without a look (large triangles are few, and
// scanning them would cost more than drawing them).
const CULL_SCAN_TILES: u32 = 256u;
const CULL_RUN: u32 = 32u;

@group(0) @binding(0) var<uniform> cull: GpuCull;
@group(0) @binding(1) var<uniform> frame: GpuFrame;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var<storage, read> tiles: array<u32>;
// Per run: (box min, cos of the cone's half angle), (box max, its sine), (cone axis, 1 when the
// run has a cone: every triangle's normal within 90 degrees of the axis).
@group(0) @binding(4) var<storage, read> runs: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read> indices: array<u32>;
// Lattice sample of each slot of this batch.
@group(0) @binding(6) var<storage, read> slots: array<u32>;
@group(0) @binding(7) var<storage, read_write> culled: array<u32>;
// Five words per slot: index count, instance count, first index, base vertex, first instance.
@group(0) @binding(8) var<storage, read_write> args: array<atomic<u32>>;
// Vertex positions, one vec4 each (w unused): one load per vertex (SceneGpu::positions).
@group(0) @binding(9) var<storage, read> positions: array<vec4<f32>>;
// The runs phase 1 kept, as slot * run count + run.
@group(0) @binding(10) var<storage, read_write> kept_runs: array<u32>;
// [runs listed, phase 2's workgroups per row].
@group(0) @binding(11) var<storage, read_write> control: array<atomic<u32>>;
// Phase 2's dispatch (x, y, z): a workgroup per listed run.
@group(0) @binding(12) var<storage, read_write> dispatch: array<u32>;

// Projected bounds: texel box and least stored depth. `behind`: a point at or behind the
// sample's plane, whose projection bounds nothing.
struct Bounds {
    lo: vec2<f32>,
    hi: vec2<f32>,
    z: f32,
    behind: bool,
}

fn empty_bounds() -> Bounds {
    return Bounds(vec2<f32>(3.0e38), vec2<f32>(-3.0e38), 3.0e38, false);
}

// Grows `b` by world point p. Stored depth z/w is a linear-fractional function of the point: over
// a box its least value is at a corner, and a fragment's depth interpolates its triangle's vertices.
fn add_point(s: GpuSample, b: ptr<function, Bounds>, p: vec3<f32>) {
    let clip = s.light_from_world * vec4<f32>(p, 1.0);
    if (clip.w <= 0.0) {
        (*b).behind = true;
        return;
    }
    let size = f32(frame.map_size);
    let t = vec2<f32>((clip.x / clip.w * 0.5 + 0.5) * size, (0.5 - clip.y / clip.w * 0.5) * size);
    (*b).lo = min((*b).lo, t);
    (*b).hi = max((*b).hi, t);
    (*b).z = min((*b).z, clip.z / clip.w);
}

// Whether geometry within bounds `b` can turn a tested pixel of sample k from lit to shadowed: a
// texel centre (i + 0.5) within CULL_MARGIN of its texel box lies in a tile whose largest tested
// limit its least depth would shadow. Other tested texels keep their outcome: the test is
// monotone in the stored depth and in the limit.
fn reaches(s: GpuSample, k: u32, b: Bounds) -> bool {
    if (b.behind) {
        return true;
    }
    let last = f32(frame.map_size - 1u);
    let a = ceil(b.lo - CULL_MARGIN - 0.5);
    let c = floor(b.hi + CULL_MARGIN - 0.5);
    if (c.x < 0.0 || c.y < 0.0 || a.x > last || a.y > last || a.x > c.x || a.y > c.y) {
        return false;
    }
    let t0 = vec2<u32>(clamp(a, vec2<f32>(0.0), vec2<f32>(last))) * CULL_TILES / frame.map_size;
    let t1 = vec2<u32>(clamp(c, vec2<f32>(0.0), vec2<f32>(last))) * CULL_TILES / frame.map_size;
    if ((t1.x - t0.x + 1u) * (t1.y - t0.y + 1u) > CULL_SCAN_TILES) {
        return true;
    }
    var nearest: ShadowLookup;
    nearest.kind = LOOKUP_COMPARE;
    let z_lo = b.z - CULL_DEPTH_SLACK;
    for (var y = t0.y; y <= t1.y; y = y + 1u) {
        for (var x = t0.x; x <= t1.x; x = x + 1u) {
            let limit = tiles[k * CULL_TILE_WORDS + y * CULL_TILES + x];
            nearest.depth_limit = bitcast<f32>(limit);
            if (limit != 0u && shadow_compare(s, nearest, z_lo) == 0u) {
                return true;
            }
        }
    }
    return false;
}

fn run_keeps(s: GpuSample, k: u32, r: u32) -> bool {
    let lo = runs[r * 3u];
    let hi = runs[r * 3u + 1u];
    var axis = runs[r * 3u + 2u];
    if (cull.cull_face == 2u) {
        axis = vec4<f32>(-axis.xyz, axis.w);
    }
    // A light at infinity (an orthographic map) culls no run: it has no eye to face away from.
    if (cull.cull_face != 0u && s.position.w == 1.0 && faces_away(s.position.xyz, lo, hi, axis)) {
        return false;
    }
    var b = empty_bounds();
    for (var c = 0u; c < 8u; c = c + 1u) {
        add_point(s, &b, select(lo.xyz, hi.xyz, vec3<bool>((c & 1u) != 0u, (c & 2u) != 0u, (c & 4u) != 0u)));
    }
    return reaches(s, k, b);
}

fn triangle_keeps(s: GpuSample, k: u32, t: u32) -> bool {
    var b = empty_bounds();
    for (var j = 0u; j < 3u; j = j + 1u) {
        add_point(s, &b, positions[indices[t * 3u + j]].xyz);
    }
    return reaches(s, k, b);
}

// Phase 1, one invocation per run of one slot (workgroup row y): runs that pass are listed, as
// slot * run count + run, for phase 2. Slot and sample come from the workgroup's id, so a CPU
// device loads them once per workgroup. No workgroup barrier: CPU devices run barriers slowly.
@compute @workgroup_size(64, 1, 1)
fn main(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let slot = wg.y;
    let k = slots[slot];
    let r = (wg.z * cull.groups_x + wg.x) * 64u + lid;
    if (r == 0u) {
        atomicStore(&args[slot * 5u + 1u], 1u);
        atomicStore(&args[slot * 5u + 2u], slot * cull.slot_stride);
        atomicStore(&args[slot * 5u + 3u], 0u);
        atomicStore(&args[slot * 5u + 4u], k);
    }
    let run_count = (cull.triangle_count + CULL_RUN - 1u) / CULL_RUN;
    if (r >= run_count || !run_keeps(samples[k], k, r)) {
        return;
    }
    kept_runs[atomicAdd(&control[0], 1u)] = slot * run_count + r;
}

// Between the phases: phase 2's dispatch, a workgroup per listed run, in rows of at most 32768
// workgroups (control[1] holds the row length).
@compute @workgroup_size(1, 1, 1)
fn begin() {
    let listed = atomicLoad(&control[0]);
    let row = max(min(listed, 32768u), 1u);
    atomicStore(&control[1], row);
    dispatch[0] = row;
    dispatch[1] = (listed + row - 1u) / row;
    dispatch[2] = 1u;
}

// Phase 2, a workgroup per listed run and an invocation per triangle of it: a kept triangle is
// appended to its slot's list with one atomic.
@compute @workgroup_size(32, 1, 1)
fn triangles(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let listed = wg.y * atomicLoad(&control[1]) + wg.x;
    if (listed >= atomicLoad(&control[0])) {
        return;
    }
    let run_count = (cull.triangle_count + CULL_RUN - 1u) / CULL_RUN;
    let packed = kept_runs[listed];
    let slot = packed / run_count;
    let t = (packed % run_count) * CULL_RUN + lid;
    let k = slots[slot];
    if (t >= cull.triangle_count || !triangle_keeps(samples[k], k, t)) {
        return;
    }
    let o = slot * cull.slot_stride + atomicAdd(&args[slot * 5u], 3u);
    culled[o] = indices[t * 3u];
    culled[o + 1u] = indices[t * 3u + 1u];
    culled[o + 2u] = indices[t * 3u + 2u];
}
