//! The panorama as a picture (tone-mapped), with a method's lights or quadtree cells drawn on it.

use crate::scene::environment::panorama::luminance;
use crate::scene::environment::Environment;
use image::{Rgb, RgbImage};

/// The panorama at `width` × `width/2` (nearest source pixel), Reinhard-mapped around its mean.
pub(crate) fn panorama_picture(env: &Environment, width: u32) -> RgbImage {
    let p = &env.panorama;
    let height = width / 2;
    let mean = (p.rgb.iter().map(|c| luminance(*c) as f64).sum::<f64>() / p.rgb.len() as f64)
        .max(1e-9) as f32;
    RgbImage::from_fn(width, height, |x, y| {
        let c = p.at(x * p.width / width, y * p.height / height);
        let l = luminance(c) / mean * 0.5;
        let scale = if l > 0.0 {
            (l / (1.0 + l)) / (luminance(c) + 1e-12)
        } else {
            0.0
        };
        Rgb(c.map(|v| ((v * scale).clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0) as u8))
    })
}

/// Colour of quadtree level `l` (as the adaptive pictures: red, orange, yellow, green, blue, …).
pub(crate) fn level_colour(l: u32) -> Rgb<u8> {
    const C: [[u8; 3]; 6] = [
        [230, 40, 40],
        [240, 140, 30],
        [240, 220, 40],
        [60, 200, 70],
        [50, 120, 240],
        [180, 80, 220],
    ];
    Rgb(C[(l as usize).min(5)])
}

/// Outline of the rectangle [u0, u1) × [v0, v1) in panorama coordinates.
pub(crate) fn rect(img: &mut RgbImage, uv0: (f32, f32), uv1: (f32, f32), colour: Rgb<u8>) {
    let (w, h) = (img.width() as f32, img.height() as f32);
    let x0 = ((uv0.0 * w) as u32).min(img.width() - 1);
    let x1 = ((uv1.0 * w) as u32)
        .saturating_sub(1)
        .min(img.width() - 1)
        .max(x0);
    let y0 = ((uv0.1 * h) as u32).min(img.height() - 1);
    let y1 = ((uv1.1 * h) as u32)
        .saturating_sub(1)
        .min(img.height() - 1)
        .max(y0);
    for x in x0..=x1 {
        img.put_pixel(x, y0, colour);
        img.put_pixel(x, y1, colour);
    }
    for y in y0..=y1 {
        img.put_pixel(x0, y, colour);
        img.put_pixel(x1, y, colour);
    }
}

/// A small cross at a direction (panorama coordinates of `d` under the environment's rotation).
pub(crate) fn mark(img: &mut RgbImage, env: &Environment, d: glam::Vec3, colour: Rgb<u8>) {
    let theta = d.y.clamp(-1.0, 1.0).acos();
    let mut u = (d.z.atan2(d.x) - env.rotation_rad()) / std::f32::consts::TAU;
    u -= u.floor();
    let (x, y) = (
        (u * img.width() as f32) as i32,
        (theta / std::f32::consts::PI * img.height() as f32) as i32,
    );
    for k in -3..=3i32 {
        for (px, py) in [(x + k, y), (x, y + k)] {
            if px >= 0 && py >= 0 && (px as u32) < img.width() && (py as u32) < img.height() {
                img.put_pixel(px as u32, py as u32, colour);
            }
        }
    }
}
