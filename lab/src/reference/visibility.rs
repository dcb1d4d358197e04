//! Per-pixel visibility `V(p)`: the convention of method.md §1, traced in parallel.

use super::sampling::fill_light_samples;
use super::{RefLight, ReferenceError, ReferenceMode, SurfacePoint, Tracer};
use glam::Vec3;
use rayon::prelude::*;
use std::sync::Mutex;

/// Shadow rays stop at `dist · (1 - LIGHT_END_EPS)`, so an emitter quad that is itself part of the
/// scene geometry does not shadow its own samples.
pub const LIGHT_END_EPS: f32 = 1e-4;

/// Pixels per rayon task: small enough to balance, large enough that progress calls are rare.
const CHUNK: usize = 256;

/// `V` for every point; `None` (background) and unusable points give 0.0. Never NaN.
/// Invalid input (degenerate light, `Continuous { m: 0 }`) gives all zeros: use
/// [`try_trace_visibility`] to get the error instead.
/// `progress(n)` is called from worker threads with the number of pixels finished so far, once per
/// chunk of `CHUNK` pixels; calls are serialised and `n` only grows, ending at `points.len()`.
pub fn trace_visibility(
    tracer: &Tracer,
    points: &[Option<SurfacePoint>],
    light: &RefLight,
    mode: &ReferenceMode,
    ray_offset: f32,
    progress: &(dyn Fn(usize) + Sync),
) -> Vec<f32> {
    try_trace_visibility(tracer, points, light, mode, ray_offset, progress)
        .unwrap_or_else(|_| vec![0.0; points.len()])
}

/// [`trace_visibility`] that reports invalid input.
pub fn try_trace_visibility(
    tracer: &Tracer,
    points: &[Option<SurfacePoint>],
    light: &RefLight,
    mode: &ReferenceMode,
    ray_offset: f32,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Vec<f32>, ReferenceError> {
    let light_normal = light.normal()?;
    if mode.samples_per_pixel() == 0 {
        return Err(ReferenceError::NoSamples);
    }
    let mut out = vec![0.0f32; points.len()];
    let done = Mutex::new(0usize);
    out.par_chunks_mut(CHUNK)
        .zip(points.par_chunks(CHUNK))
        .enumerate()
        .for_each(|(chunk, (out, points))| {
            let mut samples = Vec::with_capacity(mode.samples_per_pixel());
            let mut rays = 0u64;
            for (k, (v, point)) in out.iter_mut().zip(points).enumerate() {
                let Some(point) = point else { continue };
                let pixel = (chunk * CHUNK + k) as u64;
                fill_light_samples(mode, light, pixel, &mut samples);
                let (value, n) = visibility_of(
                    tracer,
                    point,
                    light.center,
                    light_normal,
                    &samples,
                    ray_offset,
                );
                *v = value;
                rays += n;
            }
            tracer.add_rays(rays);
            // Report under the lock so a progress bar never sees the count go backwards. A panic
            // in another report only poisons the count, which is still right: keep going.
            let mut done = done.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
            *done += out.len();
            progress(*done);
        });
    Ok(out)
}

/// `V` at one point for the given light samples (any sample set, e.g. for tests or a single pixel).
pub fn point_visibility(
    tracer: &Tracer,
    point: &SurfacePoint,
    light: &RefLight,
    samples: &[Vec3],
    ray_offset: f32,
) -> Result<f32, ReferenceError> {
    let n = light.normal()?;
    let (v, rays) = visibility_of(tracer, point, light.center, n, samples, ray_offset);
    tracer.add_rays(rays);
    Ok(v)
}

/// Returns `(V, rays traced)`.
fn visibility_of(
    tracer: &Tracer,
    point: &SurfacePoint,
    light_center: Vec3,
    light_normal: Vec3,
    samples: &[Vec3],
    ray_offset: f32,
) -> (f32, u64) {
    let p = point.position;
    let normal = point.normal.normalize_or_zero();
    // A point we cannot place or orient is treated like background rather than producing NaN.
    if samples.is_empty() || !p.is_finite() || normal == Vec3::ZERO || !ray_offset.is_finite() {
        return (0.0, 0);
    }
    if (p - light_center).dot(light_normal) <= 0.0 {
        return (0.0, 0); // on or behind the light's plane: unlit
    }
    let mut lit = 0u32;
    let mut rays = 0u64;
    for &y in samples {
        let cos = normal.dot(y - p);
        if cos <= 0.0 {
            continue; // y on or below the tangent plane: the surface blocks itself
        }
        // The offset goes to y's side of the surface (after the test above that is +normal; the
        // sign is kept explicit so relaxing the test cannot push origins into the surface).
        let origin = p + normal * (ray_offset * cos.signum());
        let seg = y - origin;
        let dist = seg.length();
        // An offset that reaches the light leaves nothing in between: lit.
        let blocked = dist > 0.0 && {
            rays += 1;
            tracer.occluded_uncounted(origin, seg / dist, dist * (1.0 - LIGHT_END_EPS))
        };
        if !blocked {
            lit += 1;
        }
    }
    (lit as f32 / samples.len() as f32, rays)
}
