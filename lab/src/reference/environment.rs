//! CPU reference for environment lighting: V(p) by importance sampling the full-resolution
//! panorama (pixel chosen ∝ luminance · Δω, then a uniform direction inside the pixel) and obvhs
//! shadow rays. With samples drawn ∝ L, V is the ratio estimator
//!   V̂ = Σ_k vis_k · c_k / Σ_k c_k,  c_k = max(0, n·ω_k),
//! and its standard error (delta method) is SE = sqrt(Σ c_k² (vis_k − V̂)²) / Σ c_k, which is
//! computed per pixel and reported (docs/environment.md §3).

use crate::reference::sampling::PixelRng;
use crate::reference::{SurfacePoint, Tracer};
use crate::scene::environment::panorama::{band_solid_angle, luminance};
use crate::scene::environment::Environment;
use glam::Vec3;
use rayon::prelude::*;

/// Pixels chosen ∝ luminance · Δω: a cumulative table over the panorama's pixels.
pub struct PanoramaSampler {
    cdf: Vec<f64>,
    width: u32,
    height: u32,
}

impl PanoramaSampler {
    pub fn new(env: &Environment) -> PanoramaSampler {
        let p = &env.panorama;
        let mut cdf = Vec::with_capacity(p.rgb.len());
        let mut acc = 0.0f64;
        for y in 0..p.height {
            let angle = p.pixel_solid_angle(y) as f64;
            for x in 0..p.width {
                acc += luminance(p.at(x, y)) as f64 * angle;
                cdf.push(acc);
            }
        }
        PanoramaSampler {
            cdf,
            width: p.width,
            height: p.height,
        }
    }

    pub fn total(&self) -> f64 {
        self.cdf.last().copied().unwrap_or(0.0)
    }

    /// A direction drawn ∝ L·dω from two uniforms and a third for the pixel.
    pub fn sample(&self, env: &Environment, a: f32, b: f32, c: f32) -> Vec3 {
        let target = a as f64 * self.total();
        let k = self
            .cdf
            .partition_point(|&x| x <= target)
            .min(self.cdf.len() - 1);
        let (x, y) = (k as u32 % self.width, k as u32 / self.width);
        // Uniform in solid angle inside the pixel: φ uniform, cos θ uniform over the row's band.
        let (v0, v1) = (
            y as f32 / self.height as f32,
            (y + 1) as f32 / self.height as f32,
        );
        let (c0, c1) = (
            (std::f32::consts::PI * v0).cos(),
            (std::f32::consts::PI * v1).cos(),
        );
        let cos_theta = c0 + (c1 - c0) * c;
        let v = cos_theta.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
        env.direction((x as f32 + b) / self.width as f32, v)
    }
}

/// V and its standard error per point (None: background, V = 0).
pub struct EnvReference {
    pub values: Vec<f32>,
    pub std_error: Vec<f32>,
    pub rays: u64,
}

/// Traces V for every point with `samples` importance samples each (seeded per pixel).
#[allow(clippy::too_many_arguments)] // the tracer, the sky and every setting of one trace
pub fn trace(
    tracer: &Tracer,
    env: &Environment,
    points: &[Option<SurfacePoint>],
    samples: u32,
    offset: f32,
    t_max: f32,
    seed: u64,
    progress: &(dyn Fn(usize) + Sync),
) -> EnvReference {
    let sampler = PanoramaSampler::new(env);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let rows: Vec<(f32, f32, u64)> = points
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            if n % 256 == 0 {
                progress(n);
            }
            let Some(p) = p else { return (0.0, 0.0, 0) };
            point(
                tracer,
                env,
                &sampler,
                p,
                samples,
                offset,
                t_max,
                PixelRng::new(seed, i as u64),
            )
        })
        .collect();
    EnvReference {
        values: rows.iter().map(|r| r.0).collect(),
        std_error: rows.iter().map(|r| r.1).collect(),
        rays: rows.iter().map(|r| r.2).sum(),
    }
}

/// (V̂, standard error, rays) at one point; samples are stratified in the pixel-choice dimension.
#[allow(clippy::too_many_arguments)]
pub fn point(
    tracer: &Tracer,
    env: &Environment,
    sampler: &PanoramaSampler,
    p: &SurfacePoint,
    samples: u32,
    offset: f32,
    t_max: f32,
    mut rng: PixelRng,
) -> (f32, f32, u64) {
    if sampler.total() <= 0.0 {
        return (0.0, 0.0, 0);
    }
    let origin = p.position + p.normal * offset;
    let (mut num, mut den, mut rays) = (0.0f64, 0.0f64, 0u64);
    let mut terms = Vec::with_capacity(samples as usize);
    for k in 0..samples {
        let a = (k as f32 + rng.next_f32()) / samples as f32;
        let d = sampler.sample(env, a.min(0.99999994), rng.next_f32(), rng.next_f32());
        let c = p.normal.dot(d);
        if c <= 0.0 {
            continue;
        }
        rays += 1;
        let vis = if tracer.occluded(origin, d, t_max) {
            0.0
        } else {
            1.0
        };
        num += (vis * c) as f64;
        den += c as f64;
        terms.push((c as f64, vis as f64));
    }
    if den <= 0.0 {
        return (0.0, 0.0, rays);
    }
    let v = num / den;
    let var: f64 = terms
        .iter()
        .map(|(c, vis)| c * c * (vis - v) * (vis - v))
        .sum();
    (v as f32, (var.sqrt() / den) as f32, rays)
}

/// The exact irradiance ratio of one point under a panorama whose pixels are each unoccluded or
/// blocked by `blocked(ω)` (Riemann sum over pixel centres): for the analytic tests.
pub fn riemann_visibility(env: &Environment, n: Vec3, blocked: &dyn Fn(Vec3) -> bool) -> f64 {
    let p = &env.panorama;
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for y in 0..p.height {
        let angle = band_solid_angle(
            y as f32 / p.height as f32,
            (y + 1) as f32 / p.height as f32,
            p.width,
        ) as f64;
        for x in 0..p.width {
            let d = env.direction(
                (x as f32 + 0.5) / p.width as f32,
                (y as f32 + 0.5) / p.height as f32,
            );
            let e = luminance(p.at(x, y)) as f64 * angle * n.dot(d).max(0.0) as f64;
            den += e;
            if !blocked(d) {
                num += e;
            }
        }
    }
    if den > 0.0 {
        num / den
    } else {
        0.0
    }
}

/// (mean, max) standard error over the geometry pixels.
pub fn error_summary(r: &EnvReference, points: &[Option<SurfacePoint>]) -> (f32, f32) {
    let errs: Vec<f32> = r
        .std_error
        .iter()
        .zip(points)
        .filter(|(_, p)| p.is_some())
        .map(|(e, _)| *e)
        .collect();
    if errs.is_empty() {
        return (0.0, 0.0);
    }
    (
        errs.iter().sum::<f32>() / errs.len() as f32,
        errs.iter().copied().fold(0.0, f32::max),
    )
}
