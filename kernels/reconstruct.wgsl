// reconstruct: V(p) from the prefiltered statistic at p's place in the centre map (bilinear
// between texel centres), against p's biased receiver depth z_r (normalised like `moments`).
//   esm : min(1, E[e^{c z}] e^{-c z_p}), z_p the pixel's own (unbiased) depth
//   vsm : Chebyshev p = s^2 / (s^2 + (z_r - mu)^2) when z_r > mu, light-bleeding reduction
//         p' = clamp((p - bleed) / (1 - bleed))
//   evsm: the smaller of the Chebyshev bounds of the positive and negative warps
//   msm : Hamburger 4MSM (Peters & Klein 2015, algorithm 2) with moment bias alpha
//   csm : 1/2 + 2 sum_k (E[sin c_k z] cos(c_k z') - E[cos c_k z] sin(c_k z')) / c_k, clamped, at
//         z' = z_r - depth_offset

const FILTERED_ESM: u32 = 0u;
const FILTERED_VSM: u32 = 1u;
const FILTERED_EVSM: u32 = 2u;
const FILTERED_MSM: u32 = 3u;
const FILTERED_CSM: u32 = 4u;
const PI: f32 = 3.141592653589793;

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> settings: GpuFilter;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(5) var<storage, read> moments: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read_write> visibility: array<f32>;

fn fetch(layer: u32, x: i32, y: i32) -> vec4<f32> {
    let size = i32(frame.map_size);
    let cx = clamp(x, 0, size - 1);
    let cy = clamp(y, 0, size - 1);
    return moments[layer * frame.map_size * frame.map_size + u32(cy * size + cx)];
}

// Bilinear between texel centres at continuous texel coordinate t.
fn bilinear(layer: u32, t: vec2<f32>) -> vec4<f32> {
    let x = t - vec2<f32>(0.5);
    let i = floor(x);
    let f = x - i;
    let a = fetch(layer, i32(i.x), i32(i.y));
    let b = fetch(layer, i32(i.x) + 1, i32(i.y));
    let c = fetch(layer, i32(i.x), i32(i.y) + 1);
    let d = fetch(layer, i32(i.x) + 1, i32(i.y) + 1);
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

fn chebyshev(mean: f32, second: f32, t: f32, min_variance: f32) -> f32 {
    if (t <= mean) {
        return 1.0;
    }
    let variance = max(second - mean * mean, min_variance);
    let d = t - mean;
    return variance / (variance + d * d);
}

fn reduce_bleeding(p: f32) -> f32 {
    return clamp((p - settings.bleed) / (1.0 - settings.bleed), 0.0, 1.0);
}

// Shadow intensity (occluded fraction) of Hamburger 4MSM; b are the biased moments.
fn msm_intensity(b: vec4<f32>, z: f32) -> f32 {
    let l32d22 = -b.x * b.y + b.z;
    let d22 = -b.x * b.x + b.y;
    let squared_variance = -b.y * b.y + b.w;
    let d33d22 = squared_variance * d22 - l32d22 * l32d22;
    let inv_d22 = 1.0 / d22;
    let l32 = l32d22 * inv_d22;
    var c = vec3<f32>(1.0, z, z * z);
    c.y = c.y - b.x;
    c.z = c.z - (b.y + l32 * c.y);
    c.y = c.y * inv_d22;
    c.z = c.z * (d22 / d33d22);
    c.y = c.y - l32 * c.z;
    c.x = c.x - (c.y * b.x + c.z * b.y);
    let p = c.y / c.z;
    let q = c.x / c.z;
    let r = sqrt(max(p * p * 0.25 - q, 0.0));
    let z1 = -p * 0.5 - r;
    let z2 = -p * 0.5 + r;
    var sw = vec4<f32>(0.0);
    if (z2 < z) {
        sw = vec4<f32>(z1, z, 1.0, 1.0);
    } else if (z1 < z) {
        sw = vec4<f32>(z, z1, 0.0, 1.0);
    }
    let quotient = (sw.x * z2 - b.x * (sw.x + z2) + b.y) / ((z2 - sw.y) * (z - z1));
    return clamp(sw.z + sw.w * quotient, 0.0, 1.0);
}

fn msm_decode(m: vec4<f32>) -> vec4<f32> {
    let q = vec4<f32>(m.x - 0.035955884801, m.y, m.z, m.w);
    return vec4<f32>(
        0.2227744146 * q.x + 0.0771972861 * q.y + 0.7926986636 * q.z + 0.0319417555 * q.w,
        0.1549679261 * q.x + 0.1394629426 * q.y + 0.7963415838 * q.z - 0.1722823173 * q.w,
        0.1451988946 * q.x + 0.2120202157 * q.y + 0.7258694464 * q.z - 0.2758014811 * q.w,
        0.163127443 * q.x + 0.2591432266 * q.y + 0.6539092497 * q.z - 0.3376131734 * q.w,
    );
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) band_gid: vec3<u32>) {
    // One dispatch per band of rows (docs/gpu-frame.md §8): the pixel is the band's, V is bound from
    // the band's first pixel.
    let gid = vec3<u32>(band_gid.x, band_gid.y + frame.band_first_row, band_gid.z);
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    let s = samples[0];
    let px = map_pixel(frame, s, gbuffer_position, gbuffer_normal, vec2<i32>(gid.xy));
    if (!px.geometry) {
        return;
    }
    let index = gid.y * frame.width + gid.x - band_base(frame);
    if (px.lookup.kind != LOOKUP_COMPARE) {
        visibility[index] = select(0.0, 1.0, px.lookup.kind == LOOKUP_OUTSIDE);
        return;
    }
    let position = px.position;
    let normal = px.normal;
    let lookup = px.lookup;
    let t = px.uv;
    // Normalised as `moments` does it: the frustum's near and far, or the orthographic box's.
    let ortho = s.orthographic != 0u;
    let near = select(s.depth_lin_a / s.depth_lin_b, s.depth_lin_b, ortho);
    let far = select(s.depth_lin_a / (1.0 + s.depth_lin_b), s.depth_lin_a + s.depth_lin_b, ortho);
    let z = clamp((lookup.depth_limit - near) / (far - near), 0.0, 1.0);
    let m = bilinear(0u, t);
    var v = 1.0;
    if (settings.kind == FILTERED_ESM) {
        // ESM needs no bias (its exponential falls off smoothly) and a bias would scale V by
        // e^{c·bias}: it reads p's own depth (clip.w, or the orthographic map's linear clip.z).
        let depth_w = dot(vec4<f32>(s.light_from_world[0].w, s.light_from_world[1].w, s.light_from_world[2].w, s.light_from_world[3].w), vec4<f32>(position.xyz, 1.0));
        let depth_z = dot(vec4<f32>(s.light_from_world[0].z, s.light_from_world[1].z, s.light_from_world[2].z, s.light_from_world[3].z), vec4<f32>(position.xyz, 1.0));
        let depth = select(depth_w, s.depth_lin_a * depth_z + s.depth_lin_b, ortho);
        let zp = clamp((depth - near) / (far - near), 0.0, 1.0);
        v = min(m.x * exp(-settings.c_pos * zp), 1.0);
    } else if (settings.kind == FILTERED_VSM) {
        v = reduce_bleeding(chebyshev(m.x, m.y, z, 1e-6));
    } else if (settings.kind == FILTERED_EVSM) {
        let w = 2.0 * z - 1.0;
        let pos = exp(settings.c_pos * w);
        let neg = -exp(-settings.c_neg * w);
        let dp = 1e-3 * settings.c_pos * pos;
        let dn = 1e-3 * settings.c_neg * neg;
        let vp = chebyshev(m.x, m.y, pos, dp * dp);
        let vn = chebyshev(m.z, m.w, neg, dn * dn);
        v = reduce_bleeding(min(vp, vn));
    } else if (settings.kind == FILTERED_MSM) {
        let b = mix(msm_decode(m), vec4<f32>(0.5), settings.moment_bias);
        v = 1.0 - msm_intensity(b, z);
    } else {
        // The truncated series is 1/2 at z_occ = z_r: lit receivers are evaluated depth_offset closer.
        let zc = z - settings.depth_offset;
        var sum = 0.0;
        for (var l = 0u; l < settings.layers; l = l + 1u) {
            let e = bilinear(l, t);
            let k0 = 2u * l + 1u;
            if (k0 <= settings.order) {
                let c = PI * f32(2u * k0 - 1u);
                sum = sum + (sin(c * zc) * e.x - cos(c * zc) * e.y) / c;
            }
            if (k0 + 1u <= settings.order) {
                let c = PI * f32(2u * k0 + 1u);
                sum = sum + (sin(c * zc) * e.z - cos(c * zc) * e.w) / c;
            }
        }
        // H(z_occ - z_r) ~ 1/2 + 2 sum sin(c_k (z_occ - z_r)) / c_k; sin(a - b) expands over the stored terms.
        v = clamp(0.5 - 2.0 * sum, 0.0, 1.0);
    }
    visibility[index] = v;
}
