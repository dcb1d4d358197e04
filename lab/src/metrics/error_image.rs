//! Per-pixel error images (|error| in magma, signed error in blue-white-red) with a legend bar.

use image::{Rgb, RgbImage};

use super::colormap::{diverging, magma};
use super::compute::check_planes;
use super::font;
use super::MetricsError;

/// Colour of background (non-geometry) pixels.
pub const BACKGROUND_GREY: [u8; 3] = [96, 96, 96];
/// Colour of geometry pixels whose estimate is not finite; in neither colour map.
pub const NAN_COLOUR: [u8; 3] = [0, 255, 0];
/// Height of the legend strip appended below the image.
const LEGEND_HEIGHT: u32 = 30;

/// |estimate − reference| mapped to magma over [0, `scale`] (larger errors saturate).
/// The returned image is `width × (height + 30)`: the legend strip sits below the picture.
pub fn abs_error_image(
    estimate: &[f32],
    reference: &[f32],
    geometry_mask: &[bool],
    width: u32,
    height: u32,
    scale: f32,
) -> Result<RgbImage, MetricsError> {
    let labels = [fmt_tick(0.0), fmt_tick(scale / 2.0), fmt_tick(scale)];
    let legend = Legend {
        labels,
        ramp: magma,
    };
    render(
        estimate,
        reference,
        geometry_mask,
        width,
        height,
        scale,
        legend,
        |d| magma(d.abs() / scale),
    )
}

/// (estimate − reference) mapped to blue (too dark) – white (0) – red (too bright) over
/// [−`scale`, `scale`]. Same layout as [`abs_error_image`].
pub fn signed_error_image(
    estimate: &[f32],
    reference: &[f32],
    geometry_mask: &[bool],
    width: u32,
    height: u32,
    scale: f32,
) -> Result<RgbImage, MetricsError> {
    let s = fmt_tick(scale);
    let labels = [format!("-{s}"), "0".to_string(), format!("+{s}")];
    let legend = Legend {
        labels,
        ramp: diverging,
    };
    render(
        estimate,
        reference,
        geometry_mask,
        width,
        height,
        scale,
        legend,
        |d| diverging(0.5 + 0.5 * d / scale),
    )
}

/// Tick labels (low, middle, high) and the colour map over the legend bar, t ∈ [0,1].
struct Legend {
    labels: [String; 3],
    ramp: fn(f32) -> [u8; 3],
}

#[allow(clippy::too_many_arguments)] // private; the two public wrappers keep the API small
fn render(
    estimate: &[f32],
    reference: &[f32],
    geometry_mask: &[bool],
    width: u32,
    height: u32,
    scale: f32,
    legend: Legend,
    colour: impl Fn(f32) -> [u8; 3],
) -> Result<RgbImage, MetricsError> {
    check_planes(estimate, reference, geometry_mask, width, height)?;
    if !(scale.is_finite() && scale > 0.0) {
        return Err(MetricsError::BadScale(scale));
    }
    let total_h = height
        .checked_add(LEGEND_HEIGHT)
        .ok_or(MetricsError::BadSize { width, height })?;
    let mut img = RgbImage::from_pixel(width, total_h, Rgb([255, 255, 255]));
    for y in 0..height {
        for x in 0..width {
            let i = y as usize * width as usize + x as usize;
            let c = if !geometry_mask[i] {
                BACKGROUND_GREY
            } else if !estimate[i].is_finite() {
                NAN_COLOUR
            } else {
                colour(estimate[i] - reference[i])
            };
            img.put_pixel(x, y, Rgb(c));
        }
    }
    draw_legend(&mut img, height, &legend);
    Ok(img)
}

/// Colour ramp with ticks at both ends and the middle, numbers below when they fit.
fn draw_legend(img: &mut RgbImage, top: u32, legend: &Legend) {
    let labels = &legend.labels;
    let width = img.width();
    let margin = (width / 8).min(12);
    let (x0, x1) = (margin, width - margin); // x1 exclusive
    if x1 <= x0 + 1 {
        return;
    }
    let black = [0, 0, 0];
    for x in x0..x1 {
        let c = (legend.ramp)((x - x0) as f32 / (x1 - x0 - 1) as f32);
        for y in top + 3..top + 11 {
            img.put_pixel(x, y, Rgb(c));
        }
    }
    let ticks = [x0, (x0 + x1 - 1) / 2, x1 - 1];
    for &tx in &ticks {
        for y in top + 11..top + 15 {
            img.put_pixel(tx, y, Rgb(black));
        }
    }
    // Largest font scale at which the three labels fit side by side without overlap.
    let fits = |s: u32| {
        let w: u32 = labels.iter().map(|l| font::text_width(l, s) + 2 * s).sum();
        w <= width
    };
    let Some(scale) = [2u32, 1].into_iter().find(|&s| fits(s)) else {
        return;
    };
    for (label, &tx) in labels.iter().zip(&ticks) {
        let w = font::text_width(label, scale);
        let x = tx.saturating_sub(w / 2).min(width.saturating_sub(w));
        font::draw_text(img, x, top + 17, label, scale, black);
    }
}

/// Three significant digits, no exponent, trailing zeros trimmed ("0.25", "0.0312").
fn fmt_tick(v: f32) -> String {
    if v == 0.0 || !v.is_finite() {
        return "0".into();
    }
    let decimals = (2 - v.abs().log10().floor() as i32).clamp(0, 6) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_format() {
        assert_eq!(fmt_tick(0.25), "0.25");
        assert_eq!(fmt_tick(0.125), "0.125");
        assert_eq!(fmt_tick(1.0), "1");
        assert_eq!(fmt_tick(1.0 / 32.0), "0.0312"); // exact tie: Rust formats half to even
    }
}
