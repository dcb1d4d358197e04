// cull: for each map of a batch, the triangles that can reach the texel rectangle its pixels test
// (scope = local: compact grows one rectangle per lattice sample). A triangle is kept when the
// bounding box of its three projected vertices, widened by CULL_MARGIN texels, overlaps the
// rectangle, or when a vertex lies at or behind the sample's plane (conservative). Kept triangles
// are appended to the slot's index list, whose draw_indexed_indirect arguments this pass writes:
// the raster then draws only them. Depth-only raster with a Less test keeps the nearest fragment
// whatever the order, so the map inside the rectangle is the full raster's, texel for texel.

struct GpuCull {
    triangle_count: u32,
    // Index capacity of one slot (the whole mesh: no slot can overflow).
    slot_stride: u32,
    vertex_words: u32,
    groups_x: u32,
}

// Texels of slack around the rectangle: the rasterizer snaps vertices to sub-texel precision and
// the lookup floors, so a box this far out cannot cover a tested texel centre.
const CULL_MARGIN: f32 = 2.0;

@group(0) @binding(0) var<uniform> cull: GpuCull;
@group(0) @binding(1) var<uniform> frame: GpuFrame;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var<storage, read> rects: array<vec4<u32>>;
@group(0) @binding(4) var<storage, read> vertices: array<f32>;
@group(0) @binding(5) var<storage, read> indices: array<u32>;
// Lattice sample of each slot of this batch.
@group(0) @binding(6) var<storage, read> slots: array<u32>;
@group(0) @binding(7) var<storage, read_write> culled: array<u32>;
// Five words per slot: index count, instance count, first index, base vertex, first instance.
@group(0) @binding(8) var<storage, read_write> args: array<atomic<u32>>;

fn texel_of(s: GpuSample, v: u32) -> vec3<f32> {
    let p = vec4<f32>(vertices[v * cull.vertex_words], vertices[v * cull.vertex_words + 1u], vertices[v * cull.vertex_words + 2u], 1.0);
    let clip = s.light_from_world * p;
    let size = f32(frame.map_size);
    return vec3<f32>((clip.x / clip.w * 0.5 + 0.5) * size, (0.5 - clip.y / clip.w * 0.5) * size, clip.w);
}

fn keeps(s: GpuSample, r: vec4<u32>, t: u32) -> bool {
    if (r.x > r.z || r.y > r.w) {
        return false;
    }
    let a = texel_of(s, indices[t * 3u]);
    let b = texel_of(s, indices[t * 3u + 1u]);
    let c = texel_of(s, indices[t * 3u + 2u]);
    if (a.z <= 0.0 || b.z <= 0.0 || c.z <= 0.0) {
        return true;
    }
    let lo = min(min(a.xy, b.xy), c.xy);
    let hi = max(max(a.xy, b.xy), c.xy);
    return hi.x >= f32(r.x) - CULL_MARGIN && lo.x <= f32(r.z) + 1.0 + CULL_MARGIN
        && hi.y >= f32(r.y) - CULL_MARGIN && lo.y <= f32(r.w) + 1.0 + CULL_MARGIN;
}

// Each invocation tests TRIANGLES_PER_THREAD consecutive triangles of one slot (gid.y), then
// appends its survivors with one atomic. No workgroup barrier: CPU adapters run barriers slowly.
const TRIANGLES_PER_THREAD: u32 = 32u;

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
    let r = rects[k];
    let n = min(TRIANGLES_PER_THREAD, cull.triangle_count - first);
    var kept = 0u;
    for (var i = 0u; i < n; i = i + 1u) {
        if (keeps(s, r, first + i)) {
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
