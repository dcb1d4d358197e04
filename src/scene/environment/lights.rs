//! Lights drawn from a panorama: every pixel of a (downsampled) panorama (`env-pixels`), or K
//! directional lights from median cut (`env-shadowmaps`, the seed's baseline).

use super::panorama::{luminance, Panorama};
use super::Environment;
use crate::Result;
use glam::Vec3;

/// A directional light: unit direction towards it and its power Σ L·Δω (luminance × intensity).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvLight {
    pub(crate) direction: Vec3,
    pub(crate) power: f32,
}

/// One light per pixel of the panorama downsampled to `width` × `height`, at the pixel's centre,
/// with power L·Δω (solid-angle weighted, so the total power is kept). Black pixels are dropped.
pub fn pixel_lights(env: &Environment, width: u32, height: u32) -> Result<Vec<EnvLight>> {
    let p = env.panorama.downsample(width, height)?;
    let mut out = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        let angle = p.pixel_solid_angle(y);
        for x in 0..width {
            let power = luminance(p.at(x, y)) * angle * env.intensity;
            if power > 0.0 {
                let d = env.direction(
                    (x as f32 + 0.5) / width as f32,
                    (y as f32 + 0.5) / height as f32,
                );
                out.push(EnvLight {
                    direction: d,
                    power,
                });
            }
        }
    }
    Ok(out)
}

/// Median cut (Debevec 2005): split the panorama, weighted by luminance · Δω, into `k` regions of
/// about equal power (always along the longer side, measured in angle), one light per region at its
/// power centroid with the region's power. `k` is rounded down to a power of two.
pub(crate) fn median_cut(env: &Environment, k: u32) -> Vec<(EnvLight, [u32; 4])> {
    let p: &Panorama = &env.panorama;
    let (w, h) = (p.width as usize, p.height as usize);
    // Summed-area table of luminance · Δω.
    let mut sat = vec![0.0f64; (w + 1) * (h + 1)];
    for y in 0..h {
        let angle = p.pixel_solid_angle(y as u32) as f64;
        let mut row = 0.0;
        for x in 0..w {
            row += luminance(p.at(x as u32, y as u32)) as f64 * angle;
            sat[(y + 1) * (w + 1) + x + 1] = sat[y * (w + 1) + x + 1] + row;
        }
    }
    let sum = |x0: usize, y0: usize, x1: usize, y1: usize| {
        sat[y1 * (w + 1) + x1] - sat[y0 * (w + 1) + x1] - sat[y1 * (w + 1) + x0]
            + sat[y0 * (w + 1) + x0]
    };
    let mut regions = vec![[0usize, 0, w, h]];
    let levels = (k.max(1) as f32).log2().floor() as u32;
    for _ in 0..levels {
        let mut next = Vec::with_capacity(regions.len() * 2);
        for [x0, y0, x1, y1] in regions {
            // Width in angle: columns shrink by sin θ at the region's middle row.
            let mid = ((y0 + y1) as f32 * 0.5 + 0.5) / h as f32;
            let wide = (x1 - x0) as f32 * (std::f32::consts::PI * mid).sin() > (y1 - y0) as f32;
            let total = sum(x0, y0, x1, y1);
            if wide && x1 - x0 > 1 {
                let cut = (x0 + 1..x1)
                    .find(|&c| sum(x0, y0, c, y1) >= 0.5 * total)
                    .unwrap_or((x0 + x1) / 2);
                next.push([x0, y0, cut, y1]);
                next.push([cut, y0, x1, y1]);
            } else if y1 - y0 > 1 {
                let cut = (y0 + 1..y1)
                    .find(|&c| sum(x0, y0, x1, c) >= 0.5 * total)
                    .unwrap_or((y0 + y1) / 2);
                next.push([x0, y0, x1, cut]);
                next.push([x0, cut, x1, y1]);
            } else {
                next.push([x0, y0, x1, y1]);
            }
        }
        regions = next;
    }
    regions
        .into_iter()
        .filter_map(|[x0, y0, x1, y1]| {
            let mut power = 0.0f64;
            let mut centroid = Vec3::ZERO;
            for y in y0..y1 {
                let angle = p.pixel_solid_angle(y as u32) as f64;
                for x in x0..x1 {
                    let e = luminance(p.at(x as u32, y as u32)) as f64 * angle;
                    power += e;
                    centroid += env
                        .direction((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32)
                        * e as f32;
                }
            }
            let direction = centroid.normalize_or_zero();
            (power > 0.0 && direction != Vec3::ZERO).then_some((
                EnvLight {
                    direction,
                    power: power as f32 * env.intensity,
                },
                [x0 as u32, y0 as u32, x1 as u32, y1 as u32],
            ))
        })
        .collect()
}

/// Σ power · max(0, n·ω) over `lights`: the irradiance they give a point with normal `n`, unoccluded.
pub fn irradiance(lights: &[EnvLight], n: Vec3) -> f32 {
    lights
        .iter()
        .map(|l| l.power * n.dot(l.direction).max(0.0))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::environment::Environment;

    #[test]
    fn uniform_environment_gives_pi_l() {
        let env = Environment::new(
            "uniform",
            Panorama::uniform(256, 128, [2.0, 2.0, 2.0]),
            0.0,
            1.0,
        );
        let lights = pixel_lights(&env, 256, 128).unwrap();
        for n in [Vec3::Y, Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize()] {
            let e = irradiance(&lights, n);
            assert!(
                (e - std::f32::consts::PI * 2.0).abs() < 2e-3 * std::f32::consts::PI * 2.0,
                "n {n}: {e} vs 2π"
            );
        }
        // Downsampling keeps the power exactly (solid-angle weights).
        let coarse = pixel_lights(&env, 16, 8).unwrap();
        let total: f32 = coarse.iter().map(|l| l.power).sum();
        assert!(
            (total - 8.0 * std::f32::consts::PI).abs() < 1e-3,
            "total power {total} vs 8π"
        );
    }

    #[test]
    fn median_cut_splits_power_evenly_and_finds_the_sun() {
        let mut p = Panorama::uniform(64, 32, [0.1; 3]);
        p.rgb[(8 * 64 + 40) as usize] = [500.0; 3];
        let env = Environment::new("sun", p, 0.0, 1.0);
        let lights = median_cut(&env, 8);
        assert_eq!(lights.len(), 8);
        let total: f32 = lights.iter().map(|l| l.0.power).sum();
        assert!((total as f64 - env.panorama.power()).abs() < 1e-3 * env.panorama.power());
        let sun = env.direction(40.5 / 64.0, 8.5 / 32.0);
        let brightest = lights
            .iter()
            .max_by(|a, b| a.0.power.total_cmp(&b.0.power))
            .unwrap();
        assert!(
            brightest.0.direction.dot(sun) > 0.99,
            "brightest light {:?} vs sun {sun}",
            brightest.0.direction
        );
    }
}
