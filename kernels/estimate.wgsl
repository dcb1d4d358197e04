// estimate: per pixel, the sums an error estimate without a reference is made of
// (docs/error-estimate.md), over one range of a fixed sample set's maps:
//  x, y: the two half-set differences of V, between the grid's even and odd columns and rows
//        (sample i's signed weight in each is its split);
//  z:    Σ w (v − f), the nearest-texel test against the bilinear one (the maps' quantization);
//  w:    Σ w (v₂ − v), the test with doubled bias and normal offset against the frame's (the bias);
// and, in `maps`, the half-set differences of z and w (columns, rows, as x and y split V): the
// part of the maps' error that averages out over samples (docs/error-estimate.md §3).
// Blocks of consecutive samples in sample order, as shade adds them (kernels/shade.wgsl): full
// blocks of ESTIMATE_BLOCK, then 8, 4, 2, 1, one entry point per size, each unrolled, the block's
// samples, weights and splits in uniform buffers read at constant offsets, one workgroup per
// geometry tile. The twin (stages/twin/estimate.rs) adds in the same order.
const ESTIMATE_BLOCK: u32 = 16u;

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> block_samples: array<GpuSample, ESTIMATE_BLOCK>;
// Weight j is block_weights[j / 4][j % 4]; split j is block_split[j / 2].xy or .zw.
@group(0) @binding(2) var<uniform> block_weights: array<vec4<f32>, 4>;
@group(0) @binding(3) var<uniform> block_split: array<vec4<f32>, 8>;
@group(0) @binding(4) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(5) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(6) var shadow_maps: ShadowMaps;
struct EstimateSums {
    // x, y, z, w above.
    terms: vec4<f32>,
    // (column, row) half-set differences of z, then of w.
    maps: vec4<f32>,
}

@group(0) @binding(7) var<storage, read_write> sums: array<EstimateSums>;
@group(0) @binding(8) var<storage, read> tile_list: array<u32>;

// One tap of the bilinear test: texel centre t, compared against the limit moved along the
// receiver's slope by the tap's distance (as pcf does).
fn tap(s: GpuSample, limit: f32, slope: f32, uv: vec2<f32>, t: vec2<f32>) -> f32 {
    return tap_lit(frame, s, shadow_maps, limit - length(t - uv) * slope, t);
}

// The four texels around the lookup point, weighted by where the point lies between their centres.
fn bilinear(s: GpuSample, lookup: ShadowLookup, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let uv = shadow_lookup_uv(frame, s, p, n);
    let slope = slope_per_texel(frame, s, p, n);
    let base = floor(uv - vec2<f32>(0.5)) + vec2<f32>(0.5);
    let frac = uv - base;
    let limit = lookup.depth_limit;
    var f = (1.0 - frac.x) * (1.0 - frac.y) * tap(s, limit, slope, uv, base);
    f = f + frac.x * (1.0 - frac.y) * tap(s, limit, slope, uv, base + vec2<f32>(1.0, 0.0));
    f = f + (1.0 - frac.x) * frac.y * tap(s, limit, slope, uv, base + vec2<f32>(0.0, 1.0));
    f = f + frac.x * frac.y * tap(s, limit, slope, uv, base + vec2<f32>(1.0, 1.0));
    return f;
}

// The frame with doubled bias and normal offset, made once per invocation (estimate_block), not
// once per sample.
var<private> doubled: GpuFrame;

// acc + sample j's eight terms at p (normal n).
fn add1(acc: EstimateSums, j: u32, p: vec3<f32>, n: vec3<f32>) -> EstimateSums {
    let s = block_samples[j];
    let w = block_weights[j / 4u][j % 4u];
    let pair = block_split[j / 2u];
    let split = select(pair.xy, pair.zw, (j % 2u) == 1u);
    let lookup = shadow_lookup(frame, s, p, n);
    let v = f32(shadow_compare(s, lookup, map_depth(frame, shadow_maps, s, lookup.texel)));
    let f = select(v, bilinear(s, lookup, p, n), lookup.kind == LOOKUP_COMPARE);
    let wide = shadow_lookup(doubled, s, p, n);
    let v2 = f32(shadow_compare(s, wide, map_depth(frame, shadow_maps, s, wide.texel)));
    let q = v - f;
    let b = v2 - v;
    let t = acc.terms;
    let m = acc.maps;
    return EstimateSums(
        vec4<f32>(t.x + split.x * v, t.y + split.y * v, t.z + w * q, t.w + w * b),
        vec4<f32>(m.x + split.x * q, m.y + split.y * q, m.z + split.x * b, m.w + split.y * b),
    );
}

fn add2(acc: EstimateSums, j: u32, p: vec3<f32>, n: vec3<f32>) -> EstimateSums {
    return add1(add1(acc, j, p, n), j + 1u, p, n);
}

fn add4(acc: EstimateSums, j: u32, p: vec3<f32>, n: vec3<f32>) -> EstimateSums {
    return add2(add2(acc, j, p, n), j + 2u, p, n);
}

fn add8(acc: EstimateSums, j: u32, p: vec3<f32>, n: vec3<f32>) -> EstimateSums {
    return add4(add4(acc, j, p, n), j + 4u, p, n);
}

fn add16(acc: EstimateSums, j: u32, p: vec3<f32>, n: vec3<f32>) -> EstimateSums {
    return add8(add8(acc, j, p, n), j + 8u, p, n);
}

// The block's first `count` samples (a constant in each entry point). No early return: pixels
// outside the image or without geometry compute like the others and skip only the store.
fn estimate_block(gid: vec3<u32>, count: u32) {
    let inside = gid.x < frame.width && gid.y < frame.height;
    let pixel = vec2<i32>(gid.xy);
    let position = textureLoad(gbuffer_position, pixel, 0);
    let p = position.xyz;
    let n = textureLoad(gbuffer_normal, pixel, 0).xyz;
    doubled = frame;
    doubled.bias_constant = frame.bias_constant * 2.0;
    doubled.bias_slope = frame.bias_slope * 2.0;
    doubled.normal_offset = frame.normal_offset * 2.0;
    let index = gid.y * frame.width + gid.x;
    var acc = sums[min(index, arrayLength(&sums) - 1u)];
    switch (count) {
        case 16u: { acc = add16(acc, 0u, p, n); }
        case 8u: { acc = add8(acc, 0u, p, n); }
        case 4u: { acc = add4(acc, 0u, p, n); }
        case 2u: { acc = add2(acc, 0u, p, n); }
        default: { acc = add1(acc, 0u, p, n); }
    }
    if (inside && position.w != 0.0) {
        sums[index] = acc;
    }
}

@compute @workgroup_size(8, 8, 1)
fn block16(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    estimate_block(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width), 16u);
}

@compute @workgroup_size(8, 8, 1)
fn block8(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    estimate_block(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width), 8u);
}

@compute @workgroup_size(8, 8, 1)
fn block4(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    estimate_block(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width), 4u);
}

@compute @workgroup_size(8, 8, 1)
fn block2(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    estimate_block(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width), 2u);
}

@compute @workgroup_size(8, 8, 1)
fn block1(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    estimate_block(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width), 1u);
}
