// hybrid_build: merges one full-resolution map (a layer of the transient raster) into the hybrid
// store (seed 003, docs/hybrid.md). A 2x2 block merges when each of its four depths differs from
// their mean by at most eps; the second level merges 2x2 blocks of merged texels by the same rule on
// their means. One thread per coarse texel (2^levels full texels per side):
//   classify ─► scan_rows (one thread per row: the seed's line sweep) ─► scan_total (one thread:
//   allocates the map in the pool, or flags overflow) ─► emit (coarse nodes, children, the root).
// The node format is the one kernels/shared/maps_hybrid.wgsl reads.

struct GpuHybridBuild {
    levels: u32,
    coarse: u32,
    layer: u32,
    slot: u32,
    capacity: u32,
    eps: f32,
    pad0: u32,
    pad1: u32,
}

// Written by one thread at a time (scan_total), read by the others: no atomics needed.
struct GpuHybridControl {
    used: u32,
    overflow: u32,
    map_base: u32,
    built: u32,
}

const HYBRID_POOL_WIDTH_LOG2: u32 = 12u;
const HYBRID_CHILDREN: u32 = 0x80000000u;

@group(0) @binding(0) var<uniform> build: GpuHybridBuild;
@group(0) @binding(1) var raster: texture_depth_2d_array;
@group(0) @binding(2) var<storage, read_write> offsets: array<u32>;
@group(0) @binding(3) var<storage, read_write> row_starts: array<u32>;
@group(0) @binding(4) var<storage, read_write> control: GpuHybridControl;
@group(0) @binding(5) var pool: texture_storage_2d<r32uint, write>;

fn full_depth(x: u32, y: u32) -> f32 {
    return textureLoad(raster, vec2<u32>(x, y), i32(build.layer), 0);
}

fn block_mean(a: f32, b: f32, c: f32, d: f32) -> f32 {
    return ((a + b) + (c + d)) * 0.25;
}

fn block_flat(a: f32, b: f32, c: f32, d: f32, mean: f32) -> bool {
    return abs(a - mean) <= build.eps && abs(b - mean) <= build.eps && abs(c - mean) <= build.eps && abs(d - mean) <= build.eps;
}

// One 2x2 block of full texels at (x, y) (its top-left texel).
struct Block {
    d: vec4<f32>,
    mean: f32,
    flat: bool,
}

fn fine_block(x: u32, y: u32) -> Block {
    var b: Block;
    b.d = vec4<f32>(full_depth(x, y), full_depth(x + 1u, y), full_depth(x, y + 1u), full_depth(x + 1u, y + 1u));
    b.mean = block_mean(b.d.x, b.d.y, b.d.z, b.d.w);
    b.flat = block_flat(b.d.x, b.d.y, b.d.z, b.d.w, b.mean);
    return b;
}

// A coarse texel: its children (levels = 2: four fine blocks; levels = 1: one block).
struct Coarse {
    child: array<Block, 4>,
    mean: f32,
    flat: bool,
    words: u32,
}

fn coarse_texel(c: vec2<u32>) -> Coarse {
    var out: Coarse;
    if (build.levels == 1u) {
        out.child[0] = fine_block(c.x * 2u, c.y * 2u);
        out.mean = out.child[0].mean;
        out.flat = out.child[0].flat;
        out.words = select(4u, 0u, out.flat);
        return out;
    }
    var all_flat = true;
    var open = 0u;
    for (var q = 0u; q < 4u; q = q + 1u) {
        let b = fine_block(c.x * 4u + (q & 1u) * 2u, c.y * 4u + (q >> 1u) * 2u);
        out.child[q] = b;
        all_flat = all_flat && b.flat;
        open = open + select(1u, 0u, b.flat);
    }
    let m = vec4<f32>(out.child[0].mean, out.child[1].mean, out.child[2].mean, out.child[3].mean);
    out.mean = block_mean(m.x, m.y, m.z, m.w);
    out.flat = all_flat && block_flat(m.x, m.y, m.z, m.w, out.mean);
    // A coarse node that does not merge points at 4 mid nodes, each a depth or 4 full texels.
    out.words = select(4u + 4u * open, 0u, out.flat);
    return out;
}

fn store_word(a: u32, v: u32) {
    let column = a & ((1u << HYBRID_POOL_WIDTH_LOG2) - 1u);
    textureStore(pool, vec2<u32>(column, a >> HYBRID_POOL_WIDTH_LOG2), vec4<u32>(v, 0u, 0u, 0u));
}

@compute @workgroup_size(8, 8, 1)
fn classify(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= build.coarse || gid.y >= build.coarse) {
        return;
    }
    offsets[gid.y * build.coarse + gid.x] = coarse_texel(gid.xy).words;
}

// Row y: child words of each coarse texel become exclusive offsets within the row.
@compute @workgroup_size(64, 1, 1)
fn scan_rows(@builtin(global_invocation_id) gid: vec3<u32>) {
    let y = gid.x;
    if (y >= build.coarse) {
        return;
    }
    var sum = 0u;
    for (var x = 0u; x < build.coarse; x = x + 1u) {
        let i = y * build.coarse + x;
        let words = offsets[i];
        offsets[i] = sum;
        sum = sum + words;
    }
    row_starts[y] = sum;
}

@compute @workgroup_size(1, 1, 1)
fn scan_total() {
    var sum = 0u;
    for (var y = 0u; y < build.coarse; y = y + 1u) {
        let words = row_starts[y];
        row_starts[y] = sum;
        sum = sum + words;
    }
    let total = build.coarse * build.coarse + sum;
    // Once one map does not fit, the later ones of this submission are not built either: the host
    // shades what the store holds and builds them again from the raster.
    if (control.overflow != 0u || total > build.capacity - min(control.used, build.capacity)) {
        control.overflow = 1u;
        return;
    }
    control.map_base = control.used;
    control.used = control.used + total;
    control.built = control.built + 1u;
    store_word(build.slot, control.map_base);
}

@compute @workgroup_size(8, 8, 1)
fn emit(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= build.coarse || gid.y >= build.coarse || control.overflow != 0u) {
        return;
    }
    let c = coarse_texel(gid.xy);
    let grid = control.map_base;
    let node = grid + gid.y * build.coarse + gid.x;
    if (c.flat) {
        store_word(node, bitcast<u32>(c.mean));
        return;
    }
    let first = grid + build.coarse * build.coarse + row_starts[gid.y] + offsets[gid.y * build.coarse + gid.x];
    store_word(node, HYBRID_CHILDREN | first);
    if (build.levels == 1u) {
        let d = c.child[0].d;
        store_word(first, bitcast<u32>(d.x));
        store_word(first + 1u, bitcast<u32>(d.y));
        store_word(first + 2u, bitcast<u32>(d.z));
        store_word(first + 3u, bitcast<u32>(d.w));
        return;
    }
    var next = first + 4u;
    for (var q = 0u; q < 4u; q = q + 1u) {
        let b = c.child[q];
        if (b.flat) {
            store_word(first + q, bitcast<u32>(b.mean));
        } else {
            store_word(first + q, HYBRID_CHILDREN | next);
            store_word(next, bitcast<u32>(b.d.x));
            store_word(next + 1u, bitcast<u32>(b.d.y));
            store_word(next + 2u, bitcast<u32>(b.d.z));
            store_word(next + 3u, bitcast<u32>(b.d.w));
            next = next + 4u;
        }
    }
}
