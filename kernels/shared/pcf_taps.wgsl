// The PCF family's tap patterns, shared by pcf and env_shadowmaps (twin: twin::pcf::pcf_taps).
// The including kernel declares `disk` (the unit-disk offsets of the disk patterns).

const PCF_BOX: u32 = 0u;
const PCF_BILINEAR: u32 = 1u;
const PCF_POISSON: u32 = 2u;
const PCF_STRATIFIED: u32 = 3u;
const PCF_ROTATED: u32 = 4u;
const TAU: f32 = 6.283185307179586;

// Offset of tap i of an n-per-side grid over [-r, r] (endpoints included; n = 1 is the centre).
fn grid_offset(i: u32, n: u32, r: f32) -> f32 {
    if (n <= 1u) {
        return 0.0;
    }
    return -r + 2.0 * r * f32(i) / f32(n - 1u);
}

// Lit taps and tap count of `settings`' pattern around map position t. Every tap's depth limit is
// moved by the receiver's slope per texel; `pixel` seeds the stratified and rotated patterns.
fn pcf_taps(frame: GpuFrame, s: GpuSample, maps: ShadowMaps, compare: sampler_comparison, settings: GpuFilter, t: vec2<f32>, limit: f32, slope: f32, pixel: vec2<u32>) -> vec2<f32> {
    var lit = 0.0;
    var count = 0u;
    if (settings.kind == PCF_BOX || settings.kind == PCF_BILINEAR) {
        let n = settings.taps;
        for (var j = 0u; j < n; j = j + 1u) {
            for (var i = 0u; i < n; i = i + 1u) {
                let o = vec2<f32>(grid_offset(i, n, settings.radius), grid_offset(j, n, settings.radius));
                let tap_limit = limit - length(o) * slope;
                if (settings.kind == PCF_BOX) {
                    lit = lit + tap_lit(frame, s, maps, tap_limit, t + o);
                } else {
                    // Stored depth at which the comparison sampler passes: lit when reference <= stored.
                    // Orthographic: the stored depth is linear, (limit - near) / range.
                    let reference = select(s.depth_lin_a / tap_limit - s.depth_lin_b, (tap_limit - s.depth_lin_b) / s.depth_lin_a, s.orthographic != 0u);
                    lit = lit + map_compare_bilinear(frame, maps, compare, s, t + o, reference);
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
                d = disk[u32(f32(settings.order) * pixel_random(pixel.x, pixel.y, i)) % settings.order];
            } else {
                let p = disk[i];
                let angle = TAU * pixel_random(pixel.x, pixel.y, i);
                let c = cos(angle);
                let sn = sin(angle);
                d = vec2<f32>(p.x * c + p.y * sn, -p.x * sn + p.y * c);
            }
            let o = d * settings.radius;
            lit = lit + tap_lit(frame, s, maps, limit - length(o) * slope, t + o);
        }
        count = settings.taps;
    }
    return vec2<f32>(lit, f32(count));
}
