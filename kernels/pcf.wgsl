// pcf: percentage-closer filtering of the centre map (seeds 001 and 004). Every tap compares the
// receiver's biased depth with one texel; V is the mean of the taps, or with `darkening` > 0 the
// seed 004 rule V = 1 - darkening * (number of shadowed taps).

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> settings: GpuFilter;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(5) var shadow_maps: ShadowMaps;
@group(0) @binding(6) var<storage, read> disk: array<vec2<f32>>;
@group(0) @binding(7) var<storage, read_write> visibility: array<f32>;
@group(0) @binding(8) var compare_sampler: sampler_comparison;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) band_gid: vec3<u32>) {
    // One dispatch per band of rows (docs/gpu-frame.md §8): the pixel is the band's, V is bound from
    // the band's first pixel.
    let gid = vec3<u32>(band_gid.x, band_gid.y + frame.band_first_row, band_gid.z);
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    // One map, or the face of a point light's cube that holds the pixel's direction.
    let s = samples[face_offset(frame, samples[0], textureLoad(gbuffer_position, vec2<i32>(gid.xy), 0).xyz)];
    let px = map_pixel(frame, s, gbuffer_position, gbuffer_normal, vec2<i32>(gid.xy));
    if (!px.geometry) {
        return;
    }
    let index = gid.y * frame.width + gid.x - band_base(frame);
    if (px.lookup.kind != LOOKUP_COMPARE) {
        visibility[index] = select(0.0, 1.0, px.lookup.kind == LOOKUP_OUTSIDE);
        return;
    }
    let slope = slope_per_texel(frame, s, px.position.xyz, px.normal);
    // The taps live in shared/pcf_taps.wgsl (env_shadowmaps filters with the same patterns).
    let taps = pcf_taps(frame, s, shadow_maps, compare_sampler, settings, px.uv, px.lookup.depth_limit, slope, gid.xy);
    let lit = taps.x;
    let count = taps.y;
    if (settings.darkening > 0.0) {
        visibility[index] = clamp(1.0 - settings.darkening * (count - lit), 0.0, 1.0);
    } else {
        visibility[index] = lit / count;
    }
}
