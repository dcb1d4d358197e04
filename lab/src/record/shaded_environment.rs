//! The shaded image of an environment-lit scene: albedo · V · E(n) / E(up), where E(n) is the
//! unoccluded irradiance of a surface with normal n (shading normal), so an unshadowed upward
//! surface shows its albedo. Exposure is fixed per scene, so every method's image compares.

use crate::render::gbuffer::GBufferCpu;
use crate::scene::environment::lights::{irradiance, pixel_lights, EnvLight};
use crate::scene::environment::Environment;
use crate::scene::Scene;
use glam::Vec3;
use image::{ImageBuffer, Rgb, RgbImage};

/// The panorama resolution the shading's irradiance integrates (fine enough for a cosine lobe).
pub const SHADE_RESOLUTION: (u32, u32) = (64, 32);

/// Lights of the shading integral: the panorama at [`SHADE_RESOLUTION`] or its own size if smaller.
pub fn shade_lights(env: &Environment) -> Vec<EnvLight> {
    let p = &env.panorama;
    let (mut w, mut h) = SHADE_RESOLUTION;
    while p.width % w != 0 || p.height % h != 0 {
        w /= 2;
        h /= 2;
        if h == 0 {
            return pixel_lights(env, p.width, p.height).unwrap_or_default();
        }
    }
    pixel_lights(env, w.min(p.width), h.min(p.height)).unwrap_or_default()
}

fn srgb(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.0031308 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

pub fn shaded_image(v: &[f32], g: &GBufferCpu, scene: &Scene, env: &Environment) -> RgbImage {
    let lights = shade_lights(env);
    let up = irradiance(&lights, Vec3::Y).max(1e-20);
    ImageBuffer::from_fn(g.width, g.height, |x, y| {
        let i = (y * g.width + x) as usize;
        if !g.is_geometry(i) {
            return Rgb([40, 44, 52]);
        }
        let n = Vec3::from_slice(&g.shading_normal[i][..3]);
        let albedo = scene
            .albedos
            .get(g.normal[i][3] as usize)
            .copied()
            .unwrap_or([0.8; 3]);
        let shade = v[i] * irradiance(&lights, n) / up;
        Rgb(albedo.map(|a| srgb(a * shade)))
    })
}
