//! Twin of `kernels/moments.wgsl`.

use crate::gpu::structs::{GpuFilter, GpuSample};

pub const FILTERED_ESM: u32 = 0;
pub const FILTERED_VSM: u32 = 1;
pub const FILTERED_EVSM: u32 = 2;
pub const FILTERED_MSM: u32 = 3;
pub const FILTERED_CSM: u32 = 4;

/// Linear depth of stored depth `d`: a / (d + b), or a·d + b on an orthographic map.
pub fn linear_depth(s: &GpuSample, d: f32) -> f32 {
    if s.orthographic != 0 {
        s.depth_lin_a * d + s.depth_lin_b
    } else {
        s.depth_lin_a / (d + s.depth_lin_b)
    }
}

/// Linear depth normalised to the frustum (or the orthographic box): (d_lin - near) / (far - near),
/// clamped to [0, 1]; near and far are the linear depths of stored 0 and 1.
pub fn normalised_depth(s: &GpuSample, linear: f32) -> f32 {
    let near = linear_depth(s, 0.0);
    let far = linear_depth(s, 1.0);
    ((linear - near) / (far - near)).clamp(0.0, 1.0)
}

/// Peters & Klein's optimised 4-moment basis, rounded to 16 bits (row vector times the matrix).
// The paper's digits, as in the kernel, so the two read alike (f32 rounds them the same).
#[allow(clippy::excessive_precision)]
pub fn msm_encode(z: f32) -> [f32; 4] {
    let z2 = z * z;
    let b = [z, z2, z2 * z, z2 * z2];
    let q = [
        -2.07224649 * b[0] + 32.23703778 * b[1] - 68.571074599 * b[2]
            + 39.3703274134 * b[3]
            + 0.035955884801,
        13.7948857237 * b[0] - 59.4683975703 * b[1] + 82.0359750338 * b[2] - 35.364903257 * b[3],
        0.105877704 * b[0] - 1.9077466311 * b[1] + 9.3496555107 * b[2] - 6.6543490743 * b[3],
        9.7924062118 * b[0] - 33.7652110555 * b[1] + 47.9456096605 * b[2] - 23.9728048165 * b[3],
    ];
    q.map(|x: f32| (x.clamp(0.0, 1.0) * 65535.0).round() / 65535.0)
}

/// Every plane of the statistic (`filter.layers` planes of map_size² vec4s) from one depth map.
pub fn moments(filter: &GpuFilter, s: &GpuSample, map: &[f32], map_size: u32) -> Vec<[f32; 4]> {
    let plane = (map_size * map_size) as usize;
    let mut out = vec![[0.0f32; 4]; plane * filter.layers as usize];
    for (texel, &d) in map.iter().enumerate() {
        let z = normalised_depth(s, linear_depth(s, d));
        match filter.kind {
            FILTERED_ESM => out[texel] = [(filter.c_pos * z).exp(), 0.0, 0.0, 0.0],
            FILTERED_VSM => out[texel] = [z, z * z, 0.0, 0.0],
            FILTERED_EVSM => {
                let w = 2.0 * z - 1.0;
                let pos = (filter.c_pos * w).exp();
                let neg = -(-filter.c_neg * w).exp();
                out[texel] = [pos, pos * pos, neg, neg * neg];
            }
            FILTERED_MSM => out[texel] = msm_encode(z),
            _ => {
                for l in 0..filter.layers {
                    let mut v = [0.0f32; 4];
                    let k0 = 2 * l + 1;
                    if k0 <= filter.order {
                        let c = std::f32::consts::PI * (2 * k0 - 1) as f32;
                        v[0] = (c * z).cos();
                        v[1] = (c * z).sin();
                    }
                    if k0 < filter.order {
                        let c = std::f32::consts::PI * (2 * k0 + 1) as f32;
                        v[2] = (c * z).cos();
                        v[3] = (c * z).sin();
                    }
                    out[l as usize * plane + texel] = v;
                }
            }
        }
    }
    out
}
