// env_shadowmaps: the seed's baseline. K directional lights from median cut, one near-orthographic
// shadow map each, box-PCF filtered like pcf.wgsl (taps within `radius` texels, the tap's limit
// moved by the receiver's slope); V = Σ power·cos·pcf / Σ power·cos (docs/environment.md §2).

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> params: GpuEnvParams;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(5) var shadow_maps: texture_depth_2d_array;
@group(0) @binding(6) var<storage, read> lights: array<GpuEnvLight>;
@group(0) @binding(7) var<storage, read_write> visibility: array<f32>;
@group(0) @binding(8) var<storage, read> ao: array<f32>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    let index = gid.y * frame.width + gid.x;
    let r = i32(params.radius);
    var num = 0.0;
    var den = 0.0;
    var geometry = false;
    for (var k = 0u; k < params.light_count; k = k + 1u) {
        let s = samples[k];
        let px = map_pixel(frame, s, gbuffer_position, gbuffer_normal, vec2<i32>(gid.xy));
        if (!px.geometry) {
            return;
        }
        let l = lights[k].direction;
        let c = dot(px.normal, l.xyz);
        if (c <= 0.0) {
            continue;
        }
        let w = l.w * c;
        den = den + w;
        if (px.lookup.kind == LOOKUP_OUTSIDE) {
            num = num + w;
            continue;
        }
        if (px.lookup.kind != LOOKUP_COMPARE) {
            continue;
        }
        let slope = slope_per_texel(frame, s, px.position, px.normal);
        var lit = 0.0;
        var taps = 0.0;
        for (var dy = -r; dy <= r; dy = dy + 1) {
            for (var dx = -r; dx <= r; dx = dx + 1) {
                let o = vec2<f32>(f32(dx), f32(dy));
                lit = lit + tap_lit(frame, s, shadow_maps, px.lookup.depth_limit - length(o) * slope, px.uv + o);
                taps = taps + 1.0;
            }
        }
        num = num + w * lit / taps;
    }
    var v = select(0.0, num / den, den > 0.0);
    if (params.use_ao != 0u) {
        v = v * ao[index];
    }
    visibility[index] = v;
}
