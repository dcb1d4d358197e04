//! Equirectangular HDR panoramas: loading, directions, solid angles, luminance and downsampling
//! with solid-angle weights (docs/environment.md §1).

use crate::{Error, Result};
use glam::Vec3;
use std::f32::consts::{PI, TAU};
use std::path::Path;

/// Rec. 709 luminance weights: the pixel light's intensity (the seed's "Factor" weights).
pub(crate) const LUMINANCE: [f32; 3] = [0.2126, 0.7152, 0.0722];

pub fn luminance(rgb: [f32; 3]) -> f32 {
    rgb[0] * LUMINANCE[0] + rgb[1] * LUMINANCE[1] + rgb[2] * LUMINANCE[2]
}

/// Linear RGB radiance per pixel, row-major, row 0 at the zenith (θ = 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Panorama {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<[f32; 3]>,
}

/// Direction of panorama coordinates (u, v) ∈ [0,1]²: φ = 2πu + rotation, θ = πv from +y (up),
/// d = (sin θ cos φ, cos θ, sin θ sin φ).
pub(crate) fn direction(u: f32, v: f32, rotation_rad: f32) -> Vec3 {
    let phi = TAU * u + rotation_rad;
    let theta = PI * v;
    let s = theta.sin();
    Vec3::new(s * phi.cos(), theta.cos(), s * phi.sin())
}

/// Solid angle of the band rows [v0, v1] of one column of a W-wide panorama: (2π/W)(cos θ0 − cos θ1).
pub fn band_solid_angle(v0: f32, v1: f32, width: u32) -> f32 {
    (TAU / width as f32) * ((PI * v0).cos() - (PI * v1).cos())
}

impl Panorama {
    /// A constant panorama (analytic tests).
    pub fn uniform(width: u32, height: u32, rgb: [f32; 3]) -> Panorama {
        Panorama {
            width,
            height,
            rgb: vec![rgb; (width * height) as usize],
        }
    }

    /// Reads an equirectangular EXR or Radiance HDR file; the width must be twice the height.
    pub(crate) fn load(path: &Path, what: &str) -> Result<Panorama> {
        let bytes = std::fs::read(path).map_err(|e| Error::Io {
            path: path.display().to_string(),
            message: format!("{what}: cannot read the panorama: {e}"),
        })?;
        let format = image::guess_format(&bytes).map_err(|e| Error::Io {
            path: path.display().to_string(),
            message: format!("{what}: not an EXR or HDR image: {e}"),
        })?;
        if !matches!(
            format,
            image::ImageFormat::OpenExr | image::ImageFormat::Hdr
        ) {
            return Err(Error::Io {
                path: path.display().to_string(),
                message: format!("{what}: is {format:?}, not an EXR or HDR panorama"),
            });
        }
        let img = image::load_from_memory_with_format(&bytes, format)
            .map_err(|e| Error::Io {
                path: path.display().to_string(),
                message: format!("{what}: cannot decode: {e}"),
            })?
            .to_rgb32f();
        let (width, height) = img.dimensions();
        if width != 2 * height || height < 2 {
            return Err(Error::Io { path: path.display().to_string(), message: format!("{what}: {width}x{height} is not an equirectangular panorama (width = 2 × height, height ≥ 2)") });
        }
        let mut rgb: Vec<[f32; 3]> = img.pixels().map(|p| p.0).collect();
        if let Some(i) = rgb.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
            return Err(Error::Io {
                path: path.display().to_string(),
                message: format!(
                    "{what}: pixel ({}, {}) = {:?} is not finite",
                    i as u32 % width,
                    i as u32 / width,
                    rgb[i]
                ),
            });
        }
        // Lossy EXR compression (DWAB) leaves tiny negative values: radiance is never negative.
        for p in &mut rgb {
            *p = p.map(|c| c.max(0.0));
        }
        Ok(Panorama { width, height, rgb })
    }

    pub fn at(&self, x: u32, y: u32) -> [f32; 3] {
        self.rgb[(y * self.width + x) as usize]
    }

    /// Solid angle of every pixel of row `y`.
    pub fn pixel_solid_angle(&self, y: u32) -> f32 {
        band_solid_angle(
            y as f32 / self.height as f32,
            (y + 1) as f32 / self.height as f32,
            self.width,
        )
    }

    /// Box-downsampled to `width` × `height` (each dividing the source size), every source pixel
    /// weighted by its solid angle, so Σ L·Δω (the panorama's power) is kept exactly per cell.
    pub(crate) fn downsample(&self, width: u32, height: u32) -> Result<Panorama> {
        if width == 0 || height == 0 || self.width % width != 0 || self.height % height != 0 {
            return Err(Error::Param(format!(
                "panorama resolution {width}x{height} must divide the source's {}x{}",
                self.width, self.height
            )));
        }
        let (fx, fy) = (self.width / width, self.height / height);
        let mut rgb = vec![[0.0f32; 3]; (width * height) as usize];
        for y in 0..height {
            let target_angle = band_solid_angle(
                y as f32 / height as f32,
                (y + 1) as f32 / height as f32,
                width,
            );
            for x in 0..width {
                let mut sum = [0.0f64; 3];
                for sy in y * fy..(y + 1) * fy {
                    let w = self.pixel_solid_angle(sy) as f64;
                    for sx in x * fx..(x + 1) * fx {
                        let p = self.at(sx, sy);
                        for c in 0..3 {
                            sum[c] += p[c] as f64 * w;
                        }
                    }
                }
                rgb[(y * width + x) as usize] = sum.map(|s| {
                    if target_angle > 0.0 {
                        (s / target_angle as f64) as f32
                    } else {
                        0.0
                    }
                });
            }
        }
        Ok(Panorama { width, height, rgb })
    }

    /// Σ luminance · Δω over every pixel (the panorama's power per unit intensity).
    pub(crate) fn power(&self) -> f64 {
        (0..self.height)
            .map(|y| {
                let w = self.pixel_solid_angle(y) as f64;
                (0..self.width)
                    .map(|x| luminance(self.at(x, y)) as f64)
                    .sum::<f64>()
                    * w
            })
            .sum()
    }
}
