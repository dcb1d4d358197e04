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
@group(0) @binding(1) var raster: ShadowMaps;
@group(0) @binding(2) var<storage, read_write> offsets: array<u32>;
@group(0) @binding(3) var<storage, read_write> row_starts: array<u32>;
@group(0) @binding(4) var<storage, read_write> control: GpuHybridControl;
@group(0) @binding(5) var pool: texture_storage_2d<r32uint, write>;
// classify's verdict per coarse texel, so emit reads the full texels again only where it must:
// the merged depth (top bit 0), or HYBRID_CHILDREN for a texel that keeps children.
@group(0) @binding(6) var<storage, read_write> coarse_nodes: array<u32>;
// Nearest, clamped: a gather returns the four texels exactly (unused by the words form).
@group(0) @binding(7) var gather_sampler: sampler;

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
    // The block's four texels (top-left, top-right, bottom-left, bottom-right), exactly as stored,
    // through the raster's map access: one gather from a depth texture, four loads of words.
    b.d = layer_block(raster, gather_sampler, vec2<u32>(x, y), build.layer, build.coarse << build.levels);
    b.mean = block_mean(b.d.x, b.d.y, b.d.z, b.d.w);
    b.flat = block_flat(b.d.x, b.d.y, b.d.z, b.d.w, b.mean);
    return b;
}

// A coarse texel: its children (levels = 2: four fine blocks b0..b3, row-major; levels = 1: b0).
// Named fields, not an array: a dynamically indexed local array spills to memory on CPU devices.
struct Coarse {
    b0: Block,
    b1: Block,
    b2: Block,
    b3: Block,
    mean: f32,
    flat: bool,
    words: u32,
}

fn coarse_texel(c: vec2<u32>) -> Coarse {
    var out: Coarse;
    if (build.levels == 1u) {
        out.b0 = fine_block(c.x * 2u, c.y * 2u);
        out.mean = out.b0.mean;
        out.flat = out.b0.flat;
        out.words = select(4u, 0u, out.flat);
        return out;
    }
    let x = c.x * 4u;
    let y = c.y * 4u;
    out.b0 = fine_block(x, y);
    out.b1 = fine_block(x + 2u, y);
    out.b2 = fine_block(x, y + 2u);
    out.b3 = fine_block(x + 2u, y + 2u);
    let all_flat = out.b0.flat && out.b1.flat && out.b2.flat && out.b3.flat;
    let open = select(1u, 0u, out.b0.flat) + select(1u, 0u, out.b1.flat) + select(1u, 0u, out.b2.flat) + select(1u, 0u, out.b3.flat);
    out.mean = block_mean(out.b0.mean, out.b1.mean, out.b2.mean, out.b3.mean);
    out.flat = all_flat && block_flat(out.b0.mean, out.b1.mean, out.b2.mean, out.b3.mean, out.mean);
    // A coarse node that does not merge points at 4 mid nodes, each a depth or 4 full texels.
    out.words = select(4u + 4u * open, 0u, out.flat);
    return out;
}

// Mid node q of a coarse texel's children at `first`; its full texels (if any) at `next`.
// Returns where the next mid node's full texels go.
fn emit_mid(first: u32, q: u32, b: Block, next: u32) -> u32 {
    if (b.flat) {
        store_word(first + q, bitcast<u32>(b.mean));
        return next;
    }
    store_word(first + q, HYBRID_CHILDREN | next);
    store_block(next, b);
    return next + 4u;
}

fn store_block(a: u32, b: Block) {
    store_word(a, bitcast<u32>(b.d.x));
    store_word(a + 1u, bitcast<u32>(b.d.y));
    store_word(a + 2u, bitcast<u32>(b.d.z));
    store_word(a + 3u, bitcast<u32>(b.d.w));
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
    let c = coarse_texel(gid.xy);
    let i = gid.y * build.coarse + gid.x;
    offsets[i] = c.words;
    coarse_nodes[i] = select(HYBRID_CHILDREN, bitcast<u32>(c.mean), c.flat);
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
    let grid = control.map_base;
    let i = gid.y * build.coarse + gid.x;
    let node = grid + i;
    let verdict = coarse_nodes[i];
    if ((verdict & HYBRID_CHILDREN) == 0u) {
        store_word(node, verdict);
        return;
    }
    let c = coarse_texel(gid.xy);
    let first = grid + build.coarse * build.coarse + row_starts[gid.y] + offsets[gid.y * build.coarse + gid.x];
    store_word(node, HYBRID_CHILDREN | first);
    if (build.levels == 1u) {
        store_block(first, c.b0);
        return;
    }
    var next = emit_mid(first, 0u, c.b0, first + 4u);
    next = emit_mid(first, 1u, c.b1, next);
    next = emit_mid(first, 2u, c.b2, next);
    emit_mid(first, 3u, c.b3, next);
}
