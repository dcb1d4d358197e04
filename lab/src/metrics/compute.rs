//! `compute`: every figure of `Metrics` in one pass over the pixels plus SSIM and FLIP.

use image::{GrayImage, RgbImage};

use super::{Metrics, MetricsError, BAD_PIXEL_THRESHOLD};

/// Checks the planar inputs against `width × height`; returns the pixel count.
pub(super) fn check_planes(
    estimate: &[f32],
    reference: &[f32],
    geometry_mask: &[bool],
    width: u32,
    height: u32,
) -> Result<usize, MetricsError> {
    let n = (width as usize)
        .checked_mul(height as usize)
        .filter(|&n| n > 0)
        .ok_or(MetricsError::BadSize { width, height })?;
    for (what, got) in [
        ("estimate", estimate.len()),
        ("reference", reference.len()),
        ("geometry_mask", geometry_mask.len()),
    ] {
        if got != n {
            return Err(MetricsError::LengthMismatch {
                what,
                got,
                expected: n,
                width,
                height,
            });
        }
    }
    if let Some(index) = reference.iter().position(|v| !v.is_finite()) {
        return Err(MetricsError::NonFiniteReference { index });
    }
    Ok(n)
}

fn check_image(
    what: &'static str,
    img: &RgbImage,
    width: u32,
    height: u32,
) -> Result<(), MetricsError> {
    if img.dimensions() != (width, height) {
        let (got_w, got_h) = img.dimensions();
        return Err(MetricsError::ImageSizeMismatch {
            what,
            got_w,
            got_h,
            width,
            height,
        });
    }
    Ok(())
}

/// Compares a visibility estimate with the reference (both V in [0,1], row-major, row 0 on top)
/// and the matching shaded sRGB images. See [`Metrics`] for the exact definition of each field.
pub fn compute(
    estimate: &[f32],
    reference: &[f32],
    geometry_mask: &[bool],
    shaded_estimate: &RgbImage,
    shaded_reference: &RgbImage,
    width: u32,
    height: u32,
) -> Result<Metrics, MetricsError> {
    let n = check_planes(estimate, reference, geometry_mask, width, height)?;
    check_image("shaded_estimate", shaded_estimate, width, height)?;
    check_image("shaded_reference", shaded_reference, width, height)?;

    // valid = geometry with a finite estimate; the only pixels any figure is taken over.
    let valid: Vec<bool> = (0..n)
        .map(|i| geometry_mask[i] && estimate[i].is_finite())
        .collect();
    let geometry = geometry_mask.iter().filter(|&&g| g).count() as u64;
    let pixels = valid.iter().filter(|&&v| v).count() as u64;
    let nan_count = geometry - pixels;
    if geometry == 0 {
        return Err(MetricsError::NoGeometry);
    }
    if pixels == 0 {
        return Err(MetricsError::NoValidPixels { nan_count });
    }

    let (mut sq, mut abs, mut max_abs, mut bad) = (0.0f64, 0.0f64, 0.0f64, 0u64);
    let (mut pen_sq, mut penumbra_pixels, mut mismatched) = (0.0f64, 0u64, 0u64);
    for i in (0..n).filter(|&i| valid[i]) {
        let (r, e) = (f64::from(reference[i]), f64::from(estimate[i]));
        let d = e - r;
        sq += d * d;
        abs += d.abs();
        max_abs = max_abs.max(d.abs());
        bad += u64::from(d.abs() > BAD_PIXEL_THRESHOLD);
        mismatched += u64::from((e >= 0.5) != (r >= 0.5));
        if r > 0.0 && r < 1.0 {
            pen_sq += d * d;
            penumbra_pixels += 1;
        }
    }
    let mse = sq / pixels as f64;
    let (flip_mean, flip_p95, flip_p99) = flip(shaded_estimate, shaded_reference, &valid)?;

    Ok(Metrics {
        rmse: mse.sqrt(),
        mae: abs / pixels as f64,
        max_abs,
        psnr: (mse > 0.0).then(|| -10.0 * mse.log10()),
        ssim: ssim(estimate, reference, geometry_mask, &valid, width, height)?,
        flip_mean,
        flip_p95,
        flip_p99,
        penumbra_rmse: (penumbra_pixels > 0).then(|| (pen_sq / penumbra_pixels as f64).sqrt()),
        bad_pixel_share: bad as f64 / pixels as f64,
        nan_count,
        pixels,
        penumbra_pixels,
        mismatch_share: mismatched as f64 / pixels as f64,
    })
}

fn quantise(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// image-compare's gray SSIM (`MSSIMSimple`: non-overlapping 8×8 windows from the top-left) on
/// 8-bit V. Each window is scored by its own call, and the scores are averaged weighted by the
/// window's valid pixels, so background windows (equal, hence SSIM 1) do not inflate the result.
/// (image-compare's per-pixel map is only exposed clamped and quantised, hence one call per window.)
fn ssim(
    estimate: &[f32],
    reference: &[f32],
    geometry_mask: &[bool],
    valid: &[bool],
    width: u32,
    height: u32,
) -> Result<f64, MetricsError> {
    const WINDOW: u32 = 8;
    let plane = |f: &dyn Fn(usize) -> u8| -> Vec<u8> { (0..valid.len()).map(f).collect() };
    let r = plane(&|i| {
        if geometry_mask[i] {
            quantise(reference[i])
        } else {
            0
        }
    });
    // Non-finite estimates copy the reference so they add no error to their window.
    let e = plane(&|i| {
        if valid[i] {
            quantise(estimate[i])
        } else {
            r[i]
        }
    });
    let to_img = |v: Vec<u8>| {
        GrayImage::from_raw(width, height, v).ok_or(MetricsError::BadSize { width, height })
    };
    let (e, r) = (to_img(e)?, to_img(r)?);
    let (mut sum, mut weight) = (0.0f64, 0u64);
    for y0 in (0..height).step_by(WINDOW as usize) {
        for x0 in (0..width).step_by(WINDOW as usize) {
            let (w, h) = (WINDOW.min(width - x0), WINDOW.min(height - y0));
            let count = (y0..y0 + h)
                .flat_map(|y| (x0..x0 + w).map(move |x| y as usize * width as usize + x as usize))
                .filter(|&i| valid[i])
                .count() as u64;
            if count == 0 {
                continue;
            }
            let crop = |img: &GrayImage| image::imageops::crop_imm(img, x0, y0, w, h).to_image();
            let sim = image_compare::gray_similarity_structure(
                &image_compare::Algorithm::MSSIMSimple,
                &crop(&e),
                &crop(&r),
            )
            .map_err(|err| MetricsError::Ssim(err.to_string()))?;
            sum += sim.score * count as f64;
            weight += count;
        }
    }
    Ok(sum / weight as f64)
}

/// LDR FLIP of the shaded images. Pixels outside `valid` get the reference colour in both
/// images so they contribute no error of their own; only valid pixels are pooled.
fn flip(
    est: &RgbImage,
    reference: &RgbImage,
    valid: &[bool],
) -> Result<(f64, f64, f64), MetricsError> {
    let (w, h) = reference.dimensions();
    let mut test = est.as_raw().clone();
    for (i, _) in valid.iter().enumerate().filter(|(_, v)| !**v) {
        test[3 * i..3 * i + 3].copy_from_slice(&reference.as_raw()[3 * i..3 * i + 3]);
    }
    let ref_img = nv_flip::FlipImageRgb8::with_data(w, h, reference.as_raw());
    let test_img = nv_flip::FlipImageRgb8::with_data(w, h, &test);
    let err = nv_flip::flip(ref_img, test_img, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec();
    let mut vals: Vec<f64> = err
        .iter()
        .zip(valid)
        .filter(|(_, v)| **v)
        .map(|(x, _)| f64::from(*x))
        .collect();
    vals.sort_by(f64::total_cmp);
    let mean = vals.iter().sum::<f64>() / vals.len() as f64;
    Ok((mean, percentile(&vals, 0.95), percentile(&vals, 0.99)))
}

/// Nearest-rank percentile of sorted, non-empty values: the smallest value with at least
/// `p·n` values at or below it.
pub(super) fn percentile(sorted: &[f64], p: f64) -> f64 {
    let rank = (p * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}
