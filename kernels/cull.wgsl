// cull: for each map of a batch, the runs of CULL_RUN consecutive triangles that can reach a texel
// its pixels test (scope = local: compact marks, per lattice sample, the culling tiles its pixels
// look up in). A run is dropped when the bounding box of its 8 projected box corners, widened by
// CULL_MARGIN texels, touches no marked tile, or when its normal cone shows every triangle facing
// the way the raster culls; a run with a corner at or behind the sample's plane is kept. Kept
// runs are appended to the slot's index list, whose draw_indexed_indirect arguments this pass
// writes: the raster draws only them. A depth-only raster with a Less test keeps the nearest
// fragment whatever the order, so the map at every tested texel is the full raster's.

struct GpuCull {
    triangle_count: u32,
    // Index capacity of one slot (the whole mesh: no slot can overflow).
    slot_stride: u32,
    // 0: the raster culls no face; 1: back faces; 2: front faces.
    cull_face: u32,
    groups_x: u32,
}

// Texels of slack around a box: the rasterizer snaps vertices to sub-texel precision, so a box
// this far out of a tile cannot cover a texel centre in it.
const CULL_MARGIN: f32 = 2.0;
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

// Whether the texel box [lo, hi], widened by CULL_MARGIN, touches a marked tile of sample k.
fn touches(k: u32, lo: vec2<f32>, hi: vec2<f32>) -> bool {
    let size = f32(frame.map_size);
    let a = lo - CULL_MARGIN;
    let b = hi + CULL_MARGIN;
    if (b.x < 0.0 || b.y < 0.0 || a.x >= size || a.y >= size) {
        return false;
    }
    let tile = size / f32(CULL_TILES);
    let t0 = vec2<u32>(clamp(floor(a / tile), vec2<f32>(0.0), vec2<f32>(f32(CULL_TILES - 1u))));
    let t1 = vec2<u32>(clamp(floor(b / tile), vec2<f32>(0.0), vec2<f32>(f32(CULL_TILES - 1u))));
    for (var y = t0.y; y <= t1.y; y = y + 1u) {
        for (var x = t0.x; x <= t1.x; x = x + 1u) {
            let bit = y * CULL_TILES + x;
            if (((tiles[k * CULL_TILE_WORDS + bit / 32u] >> (bit % 32u)) & 1u) == 1u) {
                return true;
            }
        }
    }
    return false;
}

// Whether every triangle of the run faces away from `eye` (back faces) by a safe margin: each
// normal lies within the cone, every point within the box's bounding sphere.
fn faces_away(eye: vec3<f32>, lo: vec4<f32>, hi: vec4<f32>, axis: vec4<f32>) -> bool {
    if (axis.w != 1.0) {
        return false;
    }
    let centre = (lo.xyz + hi.xyz) * 0.5;
    let radius = length(hi.xyz - lo.xyz) * 0.5;
    let v = centre - eye;
    let along = dot(v, axis.xyz);
    let across = sqrt(max(dot(v, v) - along * along, 0.0));
    return along * lo.w - across * hi.w > radius * 1.01 + length(v) * 1e-3;
}

fn run_keeps(s: GpuSample, k: u32, r: u32) -> bool {
    let lo = runs[r * 3u];
    let hi = runs[r * 3u + 1u];
    var axis = runs[r * 3u + 2u];
    if (cull.cull_face == 2u) {
        axis = vec4<f32>(-axis.xyz, axis.w);
    }
    if (cull.cull_face != 0u && faces_away(s.position.xyz, lo, hi, axis)) {
        return false;
    }
    var a = vec2<f32>(3.0e38);
    var b = vec2<f32>(-3.0e38);
    let size = f32(frame.map_size);
    for (var c = 0u; c < 8u; c = c + 1u) {
        let p = select(lo.xyz, hi.xyz, vec3<bool>((c & 1u) != 0u, (c & 2u) != 0u, (c & 4u) != 0u));
        let clip = s.light_from_world * vec4<f32>(p, 1.0);
        if (clip.w <= 0.0) {
            return true;
        }
        let t = vec2<f32>((clip.x / clip.w * 0.5 + 0.5) * size, (0.5 - clip.y / clip.w * 0.5) * size);
        a = min(a, t);
        b = max(b, t);
    }
    return touches(k, a, b);
}

// One invocation per run of one slot (gid.y): test, then append the run with one atomic. No
// workgroup barrier: CPU adapters run barriers slowly.
@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let slot = gid.y;
    let k = slots[slot];
    let r = gid.z * cull.groups_x * 64u + gid.x;
    if (r == 0u) {
        atomicStore(&args[slot * 5u + 1u], 1u);
        atomicStore(&args[slot * 5u + 2u], slot * cull.slot_stride);
        atomicStore(&args[slot * 5u + 3u], 0u);
        atomicStore(&args[slot * 5u + 4u], k);
    }
    let first = r * CULL_RUN;
    if (first >= cull.triangle_count || !run_keeps(samples[k], k, r)) {
        return;
    }
    let n = min(CULL_RUN, cull.triangle_count - first) * 3u;
    let o = slot * cull.slot_stride + atomicAdd(&args[slot * 5u], n);
    for (var i = 0u; i < n; i = i + 1u) {
        culled[o + i] = indices[first * 3u + i];
    }
}
