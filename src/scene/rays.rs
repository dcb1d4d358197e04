//! How far shadow rays start off a surface and how far environment rays go: scene-scale lengths
//! the CPU reference and the GPU ray kernels share.

/// Shadow-ray origins move this fraction of the scene's bounding-box diagonal along the normal:
/// far above f32 rounding of G-buffer positions at any scene scale, far below any feature size.
pub const RELATIVE_RAY_OFFSET: f32 = 1e-4;

/// Environment rays are infinite; this far (100 scene diagonals) is past every triangle.
pub fn env_ray_length(scene: &super::Scene) -> f32 {
    100.0 * scene.bounds.diagonal().max(1e-6)
}

pub fn ray_offset(scene: &super::Scene) -> f32 {
    RELATIVE_RAY_OFFSET * scene.bounds.diagonal()
}
