//! Known-answer tests for `compute` and the error images.

use image::{Rgb, RgbImage};

use super::*;

const W: u32 = 32;
const H: u32 = 24;

/// Shaded stand-in: grey level = V (NaN shades black, as a broken shader might).
fn shade(v: &[f32]) -> RgbImage {
    RgbImage::from_fn(W, H, |x, y| {
        let g = (v[(y * W + x) as usize].clamp(0.0, 1.0) * 255.0).round() as u8;
        Rgb([g, g, g])
    })
}

/// Reference with lit (1), umbra (0) and penumbra (a ramp strictly inside (0,1)) columns.
fn reference() -> Vec<f32> {
    (0..W * H)
        .map(|i| match i % W {
            x if x < 8 => 0.0,
            x if x < 24 => (x - 7) as f32 / 17.0,
            _ => 1.0,
        })
        .collect()
}

fn all_geometry() -> Vec<bool> {
    vec![true; (W * H) as usize]
}

fn run(est: &[f32], r: &[f32], mask: &[bool]) -> Metrics {
    compute(est, r, mask, &shade(est), &shade(r), W, H).unwrap()
}

#[test]
fn identical_images() {
    let r = reference();
    let m = run(&r, &r, &all_geometry());
    assert_eq!(m.rmse, 0.0);
    assert_eq!(m.mae, 0.0);
    assert_eq!(m.max_abs, 0.0);
    assert_eq!(m.psnr, None);
    assert_eq!(m.flip_mean, 0.0);
    assert_eq!(m.flip_p99, 0.0);
    assert_eq!(m.nan_count, 0);
    assert_eq!(m.bad_pixel_share, 0.0);
    assert_eq!(m.penumbra_rmse, Some(0.0));
    assert!((m.ssim - 1.0).abs() < 1e-12, "ssim {}", m.ssim);
    assert_eq!(m.pixels, (W * H) as u64);
    assert_eq!(m.penumbra_pixels, (16 * H) as u64);
    // JSON-safe: infinite PSNR is null and the record round-trips.
    let json = serde_json::to_string(&m).unwrap();
    assert!(json.contains("\"psnr\":null"));
    assert_eq!(serde_json::from_str::<Metrics>(&json).unwrap(), m);
}

#[test]
fn constant_offset() {
    let r = vec![0.5f32; (W * H) as usize];
    let e = vec![0.6f32; (W * H) as usize];
    let m = run(&e, &r, &all_geometry());
    assert!((m.rmse - 0.1).abs() < 1e-6, "rmse {}", m.rmse);
    assert!((m.mae - 0.1).abs() < 1e-6);
    assert!((m.max_abs - 0.1).abs() < 1e-6);
    assert!((m.psnr.unwrap() - 20.0).abs() < 1e-4, "psnr {:?}", m.psnr);
    assert_eq!(m.bad_pixel_share, 1.0);
    assert!(m.flip_mean > 0.0 && m.flip_p95 > 0.0 && m.flip_p99 >= m.flip_p95);
    assert!(m.ssim < 1.0);
}

#[test]
fn penumbra_only_error() {
    let r = reference();
    // +0.125 on penumbra pixels only (clamped values stay inside (0,1)+0.125 ≤ 1.1).
    let e: Vec<f32> = r
        .iter()
        .map(|&v| if v > 0.0 && v < 1.0 { v + 0.125 } else { v })
        .collect();
    let m = run(&e, &r, &all_geometry());
    assert!((m.penumbra_rmse.unwrap() - 0.125).abs() < 1e-6);
    // Penumbra is 16 of 32 columns: RMSE = 0.125·sqrt(1/2), bad share = 1/2.
    assert!((m.rmse - 0.125 * 0.5f64.sqrt()).abs() < 1e-6);
    assert!((m.bad_pixel_share - 0.5).abs() < 1e-12);
}

#[test]
fn no_penumbra_gives_none() {
    let r: Vec<f32> = (0..W * H).map(|i| (i % 2) as f32).collect();
    let m = run(&r, &r, &all_geometry());
    assert_eq!(m.penumbra_rmse, None);
    assert_eq!(m.penumbra_pixels, 0);
}

#[test]
fn bad_share_threshold_is_strict() {
    // Errors cycle through 0, 0.02, exactly 1/32 (representable), 0.04: only 0.04 is bad.
    let r = vec![0.5f32; (W * H) as usize];
    let offsets = [0.0, 0.02, 1.0 / 32.0, 0.04];
    let e: Vec<f32> = (0..W * H)
        .map(|i| 0.5 + offsets[(i % 4) as usize])
        .collect();
    let m = run(&e, &r, &all_geometry());
    assert!(
        (m.bad_pixel_share - 0.25).abs() < 1e-12,
        "{}",
        m.bad_pixel_share
    );
}

#[test]
fn background_is_ignored() {
    let r = reference();
    let mut e = r.clone();
    let mut mask = all_geometry();
    for i in 0..(W * 4) as usize {
        mask[i] = false; // top four rows are background ...
        e[i] = 1.0 - r[i]; // ... with wrong values that must not count
    }
    let m = compute(&e, &r, &mask, &shade(&e), &shade(&r), W, H).unwrap();
    assert_eq!(m.rmse, 0.0);
    assert_eq!(m.pixels, (W * (H - 4)) as u64);
    assert!((m.ssim - 1.0).abs() < 1e-12);
    assert_eq!(
        m.flip_mean, 0.0,
        "background differences must not leak into FLIP"
    );
}

#[test]
fn nan_counted_and_excluded() {
    let r = reference();
    let mut e = r.clone();
    let mut mask = all_geometry();
    e[3] = f32::NAN;
    e[40] = f32::INFINITY;
    e[100] = f32::NAN;
    mask[100] = false; // background NaN: not counted
    let m = compute(&e, &r, &mask, &shade(&e), &shade(&r), W, H).unwrap();
    assert_eq!(m.nan_count, 2);
    assert_eq!(m.rmse, 0.0);
    assert_eq!(m.pixels, (W * H) as u64 - 3);
    assert!(m.rmse.is_finite() && m.ssim.is_finite() && m.flip_mean.is_finite());
}

#[test]
fn bad_input_is_an_error() {
    let r = reference();
    let mask = all_geometry();
    let s = shade(&r);
    assert!(matches!(
        compute(&r[1..], &r, &mask, &s, &s, W, H),
        Err(MetricsError::LengthMismatch {
            what: "estimate",
            ..
        })
    ));
    assert!(matches!(
        compute(&r, &r, &mask, &s, &s, 0, H),
        Err(MetricsError::BadSize { .. })
    ));
    let small = RgbImage::new(W - 1, H);
    assert!(matches!(
        compute(&r, &r, &mask, &small, &s, W, H),
        Err(MetricsError::ImageSizeMismatch { .. })
    ));
    let none = vec![false; mask.len()];
    assert!(matches!(
        compute(&r, &r, &none, &s, &s, W, H),
        Err(MetricsError::NoGeometry)
    ));
    let nans = vec![f32::NAN; r.len()];
    assert!(
        matches!(compute(&nans, &r, &mask, &s, &s, W, H), Err(MetricsError::NoValidPixels { nan_count }) if nan_count == (W * H) as u64)
    );
    let mut bad_ref = r.clone();
    bad_ref[5] = f32::NAN;
    assert!(matches!(
        compute(&r, &bad_ref, &mask, &s, &s, W, H),
        Err(MetricsError::NonFiniteReference { index: 5 })
    ));
}

#[test]
fn percentile_nearest_rank() {
    let v: Vec<f64> = (1..=100).map(f64::from).collect();
    assert_eq!(compute::percentile(&v, 0.95), 95.0);
    assert_eq!(compute::percentile(&v, 0.99), 99.0);
    assert_eq!(compute::percentile(&[7.0], 0.99), 7.0);
}

#[test]
fn error_images_layout_and_colours() {
    let r = reference();
    let mut e = r.clone();
    let mut mask = all_geometry();
    mask[0] = false;
    e[1] = f32::NAN;
    e[2] = r[2] + 0.25; // saturates at scale 0.25
    let abs = abs_error_image(&e, &r, &mask, W, H, 0.25).unwrap();
    assert_eq!(abs.dimensions(), (W, H + 30));
    assert_eq!(abs.get_pixel(0, 0).0, BACKGROUND_GREY);
    assert_eq!(abs.get_pixel(1, 0).0, NAN_COLOUR);
    assert_eq!(abs.get_pixel(2, 0).0, [252, 253, 191]); // magma top
    assert_eq!(abs.get_pixel(5, 5).0, [0, 0, 4]); // zero error: magma bottom
    let signed = signed_error_image(&e, &r, &mask, W, H, 0.25).unwrap();
    assert_eq!(signed.get_pixel(5, 5).0, [247, 247, 247]);
    assert_eq!(signed.get_pixel(2, 0).0, [178, 24, 43]);
    // Legend strip: a coloured ramp and black tick/label pixels.
    let legend = image::imageops::crop_imm(&signed, 0, H, W, 30).to_image();
    assert!(legend.pixels().any(|p| p.0 == [0, 0, 0]));
    assert!(legend
        .pixels()
        .any(|p| p.0 == [247, 247, 247] || p.0[2] > 150 && p.0[0] < 100));
    assert!(matches!(
        abs_error_image(&e, &r, &mask, W, H, 0.0),
        Err(MetricsError::BadScale(_))
    ));
}

/// The error images survive a PNG round trip at their size, the masked rows in the background
/// colour (the files are kept under the temp folder only while the test runs).
#[test]
fn error_images_round_trip_through_png() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (256u32, 160u32);
    let n = (w * h) as usize;
    let r: Vec<f32> = (0..n)
        .map(|i| (i as u32 % w) as f32 / (w - 1) as f32)
        .collect();
    let e: Vec<f32> = (0..n)
        .map(|i| r[i] + 0.2 * ((i as u32 / w) as f32 / h as f32 - 0.5))
        .collect();
    let mask: Vec<bool> = (0..n).map(|i| (i as u32 / w) > 10).collect();
    for (name, img) in [
        (
            "abs.png",
            abs_error_image(&e, &r, &mask, w, h, 0.1).unwrap(),
        ),
        (
            "signed.png",
            signed_error_image(&e, &r, &mask, w, h, 0.1).unwrap(),
        ),
    ] {
        let path = dir.path().join(name);
        img.save(&path).unwrap();
        let back = image::open(&path).unwrap().to_rgb8();
        // The picture is the screen plus its colour bar underneath.
        assert_eq!(back.width(), w, "{name}");
        assert!(
            back.height() > h && back.height() == img.height(),
            "{name}: {}x{}",
            back.width(),
            back.height()
        );
        assert_eq!(back.as_raw(), img.as_raw(), "{name}: PNG is lossless");
        // Row 0 is masked out, row 100 is not: they must look different.
        assert_ne!(back.get_pixel(5, 0), back.get_pixel(5, 100), "{name}");
    }
}

#[test]
fn mismatch_share_counts_pixels_on_the_other_side_of_one_half() {
    let n = (W * H) as usize;
    let r: Vec<f32> = (0..n).map(|i| if i % 4 == 0 { 0.0 } else { 1.0 }).collect();
    let mut e = r.clone();
    // Flip every 8th pixel; nudge the others by less than one half (no mismatch).
    for (i, v) in e.iter_mut().enumerate() {
        if i % 8 == 0 {
            *v = 1.0 - *v;
        } else {
            *v = (*v - 0.4).abs();
        }
    }
    let m = run(&e, &r, &all_geometry());
    assert_eq!(m.mismatch_share, (n / 8) as f64 / n as f64);
    assert_eq!(run(&r, &r, &all_geometry()).mismatch_share, 0.0);
}
