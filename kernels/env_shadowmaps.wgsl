// env_shadowmaps: the seed's baseline. K directional lights from median cut, one near-orthographic
// shadow map each, filtered by the PCF family's patterns (shared/pcf_taps.wgsl, the same code as
// pcf.wgsl); V = Σ power·cos·pcf / Σ power·cos (docs/environment.md §2).

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> params: GpuEnvParams;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(5) var shadow_maps: ShadowMaps;
@group(0) @binding(6) var<storage, read> lights: array<GpuEnvLight>;
@group(0) @binding(7) var<storage, read_write> visibility: array<f32>;
@group(0) @binding(8) var<storage, read> ao: array<f32>;
@group(0) @binding(9) var<uniform> settings: GpuFilter;
@group(0) @binding(10) var<storage, read> disk: array<vec2<f32>>;
@group(0) @binding(11) var compare_sampler: sampler_comparison;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    let index = gid.y * frame.width + gid.x;
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
        let taps = pcf_taps(frame, s, shadow_maps, compare_sampler, settings, px.uv, px.lookup.depth_limit, slope, gid.xy);
        num = num + w * taps.x / taps.y;
    }
    var v = select(0.0, num / den, den > 0.0);
    if (params.use_ao != 0u) {
        v = v * ao[index];
    }
    visibility[index] = v;
}
