// cascades: the sun's cascaded shadow maps (docs/lights.md "Cascades"). Each pixel takes the
// cascade whose slice of the camera's depth range holds it (its view depth against the slices'
// far ends), then that cascade's map: one test (`filter = hard`) or pcf's taps (`filter = pcf`).
// It writes V and the chosen cascade, which the cascade study's texel densities read.

struct GpuCascades {
    eye: vec4<f32>,
    forward: vec4<f32>,
    // The far end of cascade i's slice is ends[i / 4][i % 4].
    ends: array<vec4<f32>, 2>,
    count: u32,
    filtering: u32,
    pad0: u32,
    pad1: u32,
}

const CASCADE_FILTER_HARD: u32 = 0u;
const CASCADE_FILTER_PCF: u32 = 1u;
// `chosen` on background pixels.
const NO_CASCADE: u32 = 0xffffffffu;

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> settings: GpuFilter;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(5) var shadow_maps: ShadowMaps;
@group(0) @binding(6) var<storage, read> disk: array<vec2<f32>>;
@group(0) @binding(7) var<storage, read_write> visibility: array<f32>;
@group(0) @binding(8) var compare_sampler: sampler_comparison;
@group(0) @binding(9) var<uniform> cascades: GpuCascades;
@group(0) @binding(10) var<storage, read_write> chosen: array<u32>;

// The cascade of a point at view depth `depth`: how many slices end in front of it. Beyond the
// last slice's end it stays in the last cascade, whose map may not hold it (then it is lit).
fn cascade_of(depth: f32) -> u32 {
    var c = 0u;
    for (var i = 0u; i + 1u < cascades.count; i = i + 1u) {
        c = c + select(0u, 1u, depth > cascades.ends[i / 4u][i % 4u]);
    }
    return c;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) band_gid: vec3<u32>) {
    // One dispatch per band of rows (docs/gpu-frame.md §8), as pcf.
    let gid = vec3<u32>(band_gid.x, band_gid.y + frame.band_first_row, band_gid.z);
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    let index = gid.y * frame.width + gid.x - band_base(frame);
    let position = textureLoad(gbuffer_position, vec2<i32>(gid.xy), 0);
    if (position.w == 0.0) {
        chosen[index] = NO_CASCADE;
        return;
    }
    let c = cascade_of(dot(position.xyz - cascades.eye.xyz, cascades.forward.xyz));
    chosen[index] = c;
    let s = samples[c];
    let px = map_pixel(frame, s, gbuffer_position, gbuffer_normal, vec2<i32>(gid.xy));
    if (px.lookup.kind != LOOKUP_COMPARE) {
        visibility[index] = select(0.0, 1.0, px.lookup.kind == LOOKUP_OUTSIDE);
        return;
    }
    if (cascades.filtering == CASCADE_FILTER_HARD) {
        visibility[index] = f32(shadow_compare(s, px.lookup, map_depth(frame, shadow_maps, s, px.lookup.texel)));
        return;
    }
    let slope = slope_per_texel(frame, s, px.position.xyz, px.normal);
    let taps = pcf_taps(frame, s, shadow_maps, compare_sampler, settings, px.uv, px.lookup.depth_limit, slope, gid.xy);
    visibility[index] = taps.x / taps.y;
}
