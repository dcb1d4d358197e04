// cull: for each map of a batch, the triangles that can reach a texel its pixels test (scope =
// local: compact marks, per lattice sample, the culling tiles its pixels look up in). A triangle
// is kept when the bounding box of its three projected vertices, widened by CULL_MARGIN texels,
// touches a marked tile, or when a vertex lies at or behind the sample's plane (conservative).
// Each invocation first tests the world bounding box of its TRIANGLES_PER_THREAD triangles the
// same way and returns at once when it touches no marked tile. Kept triangles are appended to the
// slot's index list, whose draw_indexed_indirect arguments this pass writes: the raster draws
// only them. Depth-only raster with a Less test keeps the nearest fragment whatever the order, so
// the map at every tested texel is the full raster's, texel for texel.

struct GpuCull {
    triangle_count: u32,
    // Index capacity of one slot (the whole mesh: no slot can overflow).
    slot_stride: u32,
    vertex_words: u32,
    groups_x: u32,
}

// Texels of slack around a box: the rasterizer snaps vertices to sub-texel precision, so a box
// this far out of a tile cannot cover a texel centre in it.
const CULL_MARGIN: f32 = 2.0;
const TRIANGLES_PER_THREAD: u32 = 32u;

@group(0) @binding(0) var<uniform> cull: GpuCull;
@group(0) @binding(1) var<uniform> frame: GpuFrame;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var<storage, read> tiles: array<u32>;
@group(0) @binding(4) var<storage, read> vertices: array<f32>;
@group(0) @binding(5) var<storage, read> indices: array<u32>;
// Lattice sample of each slot of this batch.
@group(0) @binding(6) var<storage, read> slots: array<u32>;
@group(0) @binding(7) var<storage, read_write> culled: array<u32>;
// Five words per slot: index count, instance count, first index, base vertex, first instance.
@group(0) @binding(8) var<storage, read_write> args: array<atomic<u32>>;
// World bounding box (min, max) of each invocation's triangles.
@group(0) @binding(9) var<storage, read> bounds: array<vec4<f32>>;

// Texel coordinate (x, y) and w of world point p in sample s's map.
fn texel_of(s: GpuSample, p: vec3<f32>) -> vec3<f32> {
    let clip = s.light_from_world * vec4<f32>(p, 1.0);
    let size = f32(frame.map_size);
    return vec3<f32>((clip.x / clip.w * 0.5 + 0.5) * size, (0.5 - clip.y / clip.w * 0.5) * size, clip.w);
}

fn vertex(v: u32) -> vec3<f32> {
    return vec3<f32>(vertices[v * cull.vertex_words], vertices[v * cull.vertex_words + 1u], vertices[v * cull.vertex_words + 2u]);
}

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

fn box_keeps(s: GpuSample, k: u32, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    var a = vec2<f32>(3.0e38);
    var b = vec2<f32>(-3.0e38);
    for (var c = 0u; c < 8u; c = c + 1u) {
        let p = select(lo, hi, vec3<bool>((c & 1u) != 0u, (c & 2u) != 0u, (c & 4u) != 0u));
        let t = texel_of(s, p);
        if (t.z <= 0.0) {
            return true;
        }
        a = min(a, t.xy);
        b = max(b, t.xy);
    }
    return touches(k, a, b);
}

fn triangle_keeps(s: GpuSample, k: u32, t: u32) -> bool {
    let a = texel_of(s, vertex(indices[t * 3u]));
    let b = texel_of(s, vertex(indices[t * 3u + 1u]));
    let c = texel_of(s, vertex(indices[t * 3u + 2u]));
    if (a.z <= 0.0 || b.z <= 0.0 || c.z <= 0.0) {
        return true;
    }
    return touches(k, min(min(a.xy, b.xy), c.xy), max(max(a.xy, b.xy), c.xy));
}

// Each invocation tests TRIANGLES_PER_THREAD consecutive triangles of one slot (gid.y), then
// appends its survivors with one atomic. No workgroup barrier: CPU adapters run barriers slowly.
@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let slot = gid.y;
    let k = slots[slot];
    let thread = gid.z * cull.groups_x * 64u + gid.x;
    if (thread == 0u) {
        atomicStore(&args[slot * 5u + 1u], 1u);
        atomicStore(&args[slot * 5u + 2u], slot * cull.slot_stride);
        atomicStore(&args[slot * 5u + 3u], 0u);
        atomicStore(&args[slot * 5u + 4u], k);
    }
    let first = thread * TRIANGLES_PER_THREAD;
    if (first >= cull.triangle_count) {
        return;
    }
    let s = samples[k];
    if (!box_keeps(s, k, bounds[thread * 2u].xyz, bounds[thread * 2u + 1u].xyz)) {
        return;
    }
    let n = min(TRIANGLES_PER_THREAD, cull.triangle_count - first);
    var kept = 0u;
    for (var i = 0u; i < n; i = i + 1u) {
        if (triangle_keeps(s, k, first + i)) {
            kept = kept | (1u << i);
        }
    }
    if (kept == 0u) {
        return;
    }
    var o = slot * cull.slot_stride + atomicAdd(&args[slot * 5u], countOneBits(kept) * 3u);
    for (var i = 0u; i < n; i = i + 1u) {
        if (((kept >> i) & 1u) == 1u) {
            let t = first + i;
            culled[o] = indices[t * 3u];
            culled[o + 1u] = indices[t * 3u + 1u];
            culled[o + 2u] = indices[t * 3u + 2u];
            o = o + 3u;
        }
    }
}
