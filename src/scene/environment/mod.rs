//! Image-based lighting from an equirectangular HDR panorama (seed 002; docs/environment.md):
//! the panorama and its pixel lights, median cut, irradiance, the GPU BVH the rays traverse and
//! the CPU reference.
//!
//! V for an environment: the unoccluded fraction of the radiance-weighted cosine integral over
//! the normal's hemisphere,
//!   V(p) = ∫ L(ω) vis(p, ω) max(0, n·ω) dω / ∫ L(ω) max(0, n·ω) dω,
//! with L the panorama's luminance (× intensity) and vis = 0 when the ray from p along ω hits a
//! triangle; 0 where the denominator is 0.

pub(crate) mod lights;
pub(crate) mod panorama;
pub(crate) mod scene;

pub(crate) use lights::{median_cut, pixel_lights, EnvLight};
pub use panorama::Panorama;

use glam::Vec3;
use std::sync::Arc;

/// A scene's `[environment]`: the panorama (loaded), its rotation about +y and an intensity scale.
#[derive(Clone, Debug)]
pub struct Environment {
    /// The file or `cache:` path as the scene gives it.
    pub source: String,
    pub panorama: Arc<Panorama>,
    pub rotation_deg: f32,
    pub intensity: f32,
}

impl Environment {
    pub fn new(
        source: impl Into<String>,
        panorama: Panorama,
        rotation_deg: f32,
        intensity: f32,
    ) -> Environment {
        Environment {
            source: source.into(),
            panorama: Arc::new(panorama),
            rotation_deg,
            intensity,
        }
    }
    pub(crate) fn rotation_rad(&self) -> f32 {
        self.rotation_deg.to_radians()
    }
    /// Direction of panorama coordinates (u, v) with this environment's rotation.
    pub fn direction(&self, u: f32, v: f32) -> Vec3 {
        panorama::direction(u, v, self.rotation_rad())
    }
    /// Bytes that change any result (cache keys).
    pub fn key_bytes(&self) -> Vec<u8> {
        let p = &self.panorama;
        let mut out = Vec::with_capacity(p.rgb.len() * 12 + 16);
        out.extend_from_slice(&p.width.to_le_bytes());
        out.extend_from_slice(&p.height.to_le_bytes());
        out.extend_from_slice(&self.rotation_deg.to_le_bytes());
        out.extend_from_slice(&self.intensity.to_le_bytes());
        for c in &p.rgb {
            for x in c {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        out
    }
}
