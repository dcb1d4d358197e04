// estimate: per pixel, the sums an error estimate without a reference is made of
// (docs/error-estimate.md), over one range of a fixed sample set's maps:
//  x, y: the two half-set differences of V, between the grid's even and odd columns and rows
//        (split[i] holds sample i's signed weight in each);
//  z:    Σ w (v − f), the nearest-texel test against the bilinear one (the maps' quantization);
//  w:    Σ w (v₂ − v), the test with doubled bias and normal offset against the frame's (the bias).
// Ranges accumulate in sample order, so the twin (stages/twin/estimate.rs) adds in the same order.

struct GpuEstimateRange {
    first: u32,
    count: u32,
    pad0: u32,
    pad1: u32,
}

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> range: GpuEstimateRange;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var<storage, read> weights: array<f32>;
@group(0) @binding(4) var<storage, read> split: array<vec2<f32>>;
@group(0) @binding(5) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(6) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(7) var shadow_maps: ShadowMaps;
@group(0) @binding(8) var<storage, read_write> sums: array<vec4<f32>>;

// The bilinear test: the four texels around the lookup point, each compared against the limit
// moved along the receiver's slope by the tap's distance (as pcf does), weighted by where the
// point lies between their centres.
fn bilinear(s: GpuSample, lookup: ShadowLookup, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let uv = shadow_lookup_uv(frame, s, p, n);
    let slope = slope_per_texel(frame, s, p, n);
    let base = floor(uv - vec2<f32>(0.5));
    let frac = uv - vec2<f32>(0.5) - base;
    var f = 0.0;
    for (var c = 0u; c < 4u; c = c + 1u) {
        let t = base + vec2<f32>(f32(c & 1u), f32(c >> 1u)) + vec2<f32>(0.5);
        let tap = tap_lit(frame, s, shadow_maps, lookup.depth_limit - length(t - uv) * slope, t);
        let w = select(1.0 - frac.x, frac.x, (c & 1u) == 1u) * select(1.0 - frac.y, frac.y, (c >> 1u) == 1u);
        f = f + w * tap;
    }
    return f;
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
    let p = position.xyz;
    let n = textureLoad(gbuffer_normal, pixel, 0).xyz;
    var doubled = frame;
    doubled.bias_constant = frame.bias_constant * 2.0;
    doubled.bias_slope = frame.bias_slope * 2.0;
    doubled.normal_offset = frame.normal_offset * 2.0;
    let index = gid.y * frame.width + gid.x;
    var acc = sums[index];
    for (var i = range.first; i < range.first + range.count; i = i + 1u) {
        let s = samples[i];
        let lookup = shadow_lookup(frame, s, p, n);
        let v = f32(shadow_compare(s, lookup, map_depth(frame, shadow_maps, s, lookup.texel)));
        var f = v;
        if (lookup.kind == LOOKUP_COMPARE) {
            f = bilinear(s, lookup, p, n);
        }
        let wide = shadow_lookup(doubled, s, p, n);
        let v2 = f32(shadow_compare(s, wide, map_depth(frame, shadow_maps, s, wide.texel)));
        let w = weights[i];
        acc = vec4<f32>(acc.x + split[i].x * v, acc.y + split[i].y * v, acc.z + w * (v - f), acc.w + w * (v2 - v));
    }
    sums[index] = acc;
}
