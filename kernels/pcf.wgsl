// pcf: percentage-closer filtering of the centre map (seeds 001 and 004). Every tap compares the
// receiver's biased depth with one texel; V is the mean of the taps, or with `darkening` > 0 the
// seed 004 rule V = 1 - darkening * (number of shadowed taps).

const PCF_BOX: u32 = 0u;
const PCF_BILINEAR: u32 = 1u;
const PCF_POISSON: u32 = 2u;
const PCF_STRATIFIED: u32 = 3u;
const PCF_ROTATED: u32 = 4u;
const TAU: f32 = 6.283185307179586;

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> settings: GpuFilter;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(5) var shadow_maps: ShadowMaps;
@group(0) @binding(6) var<storage, read> disk: array<vec2<f32>>;
@group(0) @binding(7) var<storage, read_write> visibility: array<f32>;
@group(0) @binding(8) var compare_sampler: sampler_comparison;

// Offset of tap i of an n-per-side grid over [-r, r] (endpoints included; n = 1 is the centre).
fn grid_offset(i: u32, n: u32, r: f32) -> f32 {
    if (n <= 1u) {
        return 0.0;
    }
    return -r + 2.0 * r * f32(i) / f32(n - 1u);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    let s = samples[0];
    let px = map_pixel(frame, s, gbuffer_position, gbuffer_normal, vec2<i32>(gid.xy));
    if (!px.geometry) {
        return;
    }
    let index = gid.y * frame.width + gid.x;
    if (px.lookup.kind != LOOKUP_COMPARE) {
        visibility[index] = select(0.0, 1.0, px.lookup.kind == LOOKUP_OUTSIDE);
        return;
    }
    let position = px.position;
    let normal = px.normal;
    let lookup = px.lookup;
    let t = px.uv;
    let limit = lookup.depth_limit;
    let slope = slope_per_texel(frame, s, position.xyz, normal);
    var lit = 0.0;
    var count = 0u;
    if (settings.kind == PCF_BOX || settings.kind == PCF_BILINEAR) {
        let n = settings.taps;
        for (var j = 0u; j < n; j = j + 1u) {
            for (var i = 0u; i < n; i = i + 1u) {
                let o = vec2<f32>(grid_offset(i, n, settings.radius), grid_offset(j, n, settings.radius));
                let tap_limit = limit - length(o) * slope;
                if (settings.kind == PCF_BOX) {
                    lit = lit + tap_lit(frame, s, shadow_maps, tap_limit, t + o);
                } else {
                    // Stored depth at which the comparison sampler passes: lit when reference <= stored.
                    let reference = s.depth_lin_a / tap_limit - s.depth_lin_b;
                    lit = lit + map_compare_bilinear(frame, shadow_maps, compare_sampler, s, t + o, reference);
                }
            }
        }
        count = n * n;
    } else {
        for (var i = 0u; i < settings.taps; i = i + 1u) {
            var d: vec2<f32>;
            if (settings.kind == PCF_POISSON) {
                d = disk[i];
            } else if (settings.kind == PCF_STRATIFIED) {
                d = disk[u32(f32(settings.order) * pixel_random(gid.x, gid.y, i)) % settings.order];
            } else {
                let p = disk[i];
                let angle = TAU * pixel_random(gid.x, gid.y, i);
                let c = cos(angle);
                let sn = sin(angle);
                d = vec2<f32>(p.x * c + p.y * sn, -p.x * sn + p.y * c);
            }
            let o = d * settings.radius;
            lit = lit + tap_lit(frame, s, shadow_maps, limit - length(o) * slope, t + o);
        }
        count = settings.taps;
    }
    if (settings.darkening > 0.0) {
        visibility[index] = clamp(1.0 - settings.darkening * (f32(count) - lit), 0.0, 1.0);
    } else {
        visibility[index] = lit / f32(count);
    }
}
