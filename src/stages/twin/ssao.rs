//! Twin of `kernels/ssao.wgsl`.

use crate::gpu::structs::{GpuCamera, GpuEnvParams};
use crate::render::gbuffer::GBufferCpu;
use glam::{Mat4, Vec3, Vec4};

/// The tangent frame the kernel builds from n.
pub fn frame(n: Vec3) -> (Vec3, Vec3) {
    let helper = if n.x.abs() > 0.9 { Vec3::Z } else { Vec3::X };
    let c = |a: Vec3, b: Vec3| {
        Vec3::new(
            a.y * b.z - a.z * b.y,
            a.z * b.x - a.x * b.z,
            a.x * b.y - a.y * b.x,
        )
    };
    let t = c(helper, n).normalize();
    (t, c(n, t))
}

/// (AO, occluded samples) per pixel.
pub fn ssao(
    params: &GpuEnvParams,
    camera: &GpuCamera,
    kernel: &[[f32; 4]],
    g: &GBufferCpu,
) -> (Vec<f32>, Vec<u32>) {
    let m = Mat4::from_cols_array_2d(&camera.clip_from_world);
    let eye = Vec3::new(camera.eye[0], camera.eye[1], camera.eye[2]);
    let (w, h) = (params.width as f32, params.height as f32);
    let mut ao = vec![0.0f32; g.position.len()];
    let mut occluded = vec![0u32; g.position.len()];
    for index in 0..g.position.len() {
        if !g.is_geometry(index) {
            continue;
        }
        let p = Vec3::from_slice(&g.position[index][..3]);
        let n = Vec3::from_slice(&g.normal[index][..3]);
        let (t, b) = frame(n);
        let mut count = 0u32;
        for k in &kernel[..params.light_count as usize] {
            let s = Vec3::new(k[0], k[1], k[2]) * params.radius;
            let q = p + t * s.x + b * s.y + n * s.z;
            let clip = m * Vec4::new(q.x, q.y, q.z, 1.0);
            if clip.w <= 0.0 {
                continue;
            }
            let uv = (clip.x / clip.w * 0.5 + 0.5, 0.5 - clip.y / clip.w * 0.5);
            let texel = ((uv.0 * w).floor(), (uv.1 * h).floor());
            if texel.0 < 0.0 || texel.1 < 0.0 || texel.0 >= w || texel.1 >= h {
                continue;
            }
            let stored = g.position[(texel.1 as u32 * params.width + texel.0 as u32) as usize];
            if stored[3] == 0.0 {
                continue;
            }
            let sp = Vec3::from_slice(&stored[..3]);
            if (sp - eye).length() < (q - eye).length() - params.ray_offset
                && (sp - p).length() < params.radius
            {
                count += 1;
            }
        }
        occluded[index] = count;
        ao[index] = 1.0 - count as f32 / params.light_count.max(1) as f32;
    }
    (ao, occluded)
}
