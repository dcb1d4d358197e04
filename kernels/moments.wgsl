// moments: turns the centre map's depths into the statistic a filtered method prefilters. Depth is
// linear and normalised to the frustum (or the sun's orthographic box, whose stored depth is already
// linear), z = (d_lin - near) / (far - near) in [0, 1]; `layers`
// vec4 planes of map_size^2 texels each.
//   esm : exp(c z)
//   vsm : (z, z^2)
//   evsm: (e^{c+ w}, e^{2 c+ w}, -e^{-c- w}, e^{-2 c- w}) with w = 2z - 1
//   msm : Peters & Klein's optimised 4-moment basis of (z, z^2, z^3, z^4), rounded to 16 bits
//   csm : (cos c_k z, sin c_k z) for k = 1..M, c_k = pi (2k - 1), two terms per vec4

const FILTERED_ESM: u32 = 0u;
const FILTERED_VSM: u32 = 1u;
const FILTERED_EVSM: u32 = 2u;
const FILTERED_MSM: u32 = 3u;
const FILTERED_CSM: u32 = 4u;
const PI: f32 = 3.141592653589793;

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> settings: GpuFilter;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var shadow_maps: ShadowMaps;
@group(0) @binding(4) var<storage, read_write> moments: array<vec4<f32>>;

// Row-vector product b * M of the optimised quantisation (Peters & Klein 2015, 4 x 16 bit).
fn msm_encode(z: f32) -> vec4<f32> {
    let z2 = z * z;
    let b = vec4<f32>(z, z2, z2 * z, z2 * z2);
    let q = vec4<f32>(
        -2.07224649 * b.x + 32.23703778 * b.y - 68.571074599 * b.z + 39.3703274134 * b.w + 0.035955884801,
        13.7948857237 * b.x - 59.4683975703 * b.y + 82.0359750338 * b.z - 35.364903257 * b.w,
        0.105877704 * b.x - 1.9077466311 * b.y + 9.3496555107 * b.z - 6.6543490743 * b.w,
        9.7924062118 * b.x - 33.7652110555 * b.y + 47.9456096605 * b.z - 23.9728048165 * b.w,
    );
    return round(clamp(q, vec4<f32>(0.0), vec4<f32>(1.0)) * 65535.0) / 65535.0;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = frame.map_size;
    if (gid.x >= size || gid.y >= size) {
        return;
    }
    let s = samples[0];
    let d = map_depth(frame, shadow_maps, s, vec2<i32>(gid.xy));
    let ortho = s.orthographic != 0u;
    let near = select(s.depth_lin_a / s.depth_lin_b, s.depth_lin_b, ortho);
    let far = select(s.depth_lin_a / (1.0 + s.depth_lin_b), s.depth_lin_a + s.depth_lin_b, ortho);
    let linear = select(s.depth_lin_a / (d + s.depth_lin_b), s.depth_lin_a * d + s.depth_lin_b, ortho);
    let z = clamp((linear - near) / (far - near), 0.0, 1.0);
    let texel = gid.y * size + gid.x;
    let plane = size * size;
    if (settings.kind == FILTERED_ESM) {
        moments[texel] = vec4<f32>(exp(settings.c_pos * z), 0.0, 0.0, 0.0);
    } else if (settings.kind == FILTERED_VSM) {
        moments[texel] = vec4<f32>(z, z * z, 0.0, 0.0);
    } else if (settings.kind == FILTERED_EVSM) {
        let w = 2.0 * z - 1.0;
        let pos = exp(settings.c_pos * w);
        let neg = -exp(-settings.c_neg * w);
        moments[texel] = vec4<f32>(pos, pos * pos, neg, neg * neg);
    } else if (settings.kind == FILTERED_MSM) {
        moments[texel] = msm_encode(z);
    } else {
        for (var l = 0u; l < settings.layers; l = l + 1u) {
            var v = vec4<f32>(0.0);
            let k0 = 2u * l + 1u;
            if (k0 <= settings.order) {
                let c = PI * f32(2u * k0 - 1u);
                v.x = cos(c * z);
                v.y = sin(c * z);
            }
            if (k0 + 1u <= settings.order) {
                let c = PI * f32(2u * k0 + 1u);
                v.z = cos(c * z);
                v.w = sin(c * z);
            }
            moments[l * plane + texel] = v;
        }
    }
}
