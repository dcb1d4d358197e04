//! Twin of `kernels/env_vertex_interp.wgsl`.

use crate::gpu::structs::GpuEnvParams;

/// V per pixel from V per vertex: `ids` as the barycentrics pass writes them (triangle + 1, b1
/// bits, b2 bits), `indices` the scene's index buffer. Background pixels are 0.
pub fn env_vertex_interp(
    params: &GpuEnvParams,
    ids: &[[u32; 4]],
    indices: &[u32],
    vertex_visibility: &[f32],
    ao: &[f32],
) -> Vec<f32> {
    ids.iter()
        .enumerate()
        .map(|(index, id)| {
            if id[0] == 0 {
                return 0.0;
            }
            let t = (id[0] - 1) as usize * 3;
            let (b1, b2) = (f32::from_bits(id[1]), f32::from_bits(id[2]));
            let b0 = 1.0 - b1 - b2;
            let [v0, v1, v2] = [0, 1, 2].map(|k| vertex_visibility[indices[t + k] as usize]);
            let v = b0 * v0 + b1 * v1 + b2 * v2;
            if params.use_ao != 0 {
                v * ao[index]
            } else {
                v
            }
        })
        .collect()
}
