//! Image metrics of an estimated visibility image against a reference, and error images.
//!
//! Every metric is taken over geometry pixels only (background is excluded everywhere), and
//! non-finite estimate values are counted in `nan_count` and excluded from every other figure.

mod colormap;
mod compute;
mod error_image;
mod font;

use serde::{Deserialize, Serialize};

pub use compute::compute;
pub use error_image::{abs_error_image, signed_error_image, BACKGROUND_GREY, NAN_COLOUR};

/// Threshold on |estimate - reference| above which a pixel counts as "bad" (one 5-bit step).
pub const BAD_PIXEL_THRESHOLD: f64 = 1.0 / 32.0;

/// Error figures of one visibility estimate. All JSON-safe: no NaN or infinity is ever stored.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Root-mean-square error of V over valid pixels (geometry, finite estimate).
    pub rmse: f64,
    /// Mean absolute error of V over valid pixels.
    pub mae: f64,
    /// Largest absolute error of V over valid pixels.
    pub max_abs: f64,
    /// PSNR in dB with peak 1: `10·log10(1/MSE)`. `None` (JSON `null`) when MSE is 0,
    /// i.e. infinite PSNR; readers should treat `null` as "identical".
    pub psnr: Option<f64>,
    /// Mean over valid pixels of image-compare's 8×8-block gray SSIM of V quantised to 8 bits
    /// (`round(clamp(V,0,1)·255)`); background set to 0 in both images. Caveat: image-compare
    /// 0.5 sums (co)variances over the window instead of averaging them, which equals standard
    /// SSIM with C2 divided by 64, so flat regions score lower than elsewhere: compare SSIM only
    /// with SSIM from this same code.
    pub ssim: f64,
    /// FLIP (LDR, 67 pixels per degree) of the shaded images, mean over valid pixels.
    pub flip_mean: f64,
    /// 95th percentile (nearest rank) of per-pixel FLIP over valid pixels.
    pub flip_p95: f64,
    /// 99th percentile (nearest rank) of per-pixel FLIP over valid pixels.
    pub flip_p99: f64,
    /// RMSE over valid pixels whose reference V is strictly inside (0, 1). `None` when the
    /// reference has no penumbra pixel.
    pub penumbra_rmse: Option<f64>,
    /// Share (0..1) of valid pixels with |error| > 1/32.
    pub bad_pixel_share: f64,
    /// Geometry pixels whose estimate is not finite (NaN or ±inf).
    pub nan_count: u64,
    /// Valid pixels the figures above are taken over (geometry minus non-finite estimates).
    #[serde(default)]
    pub pixels: u64,
    /// Valid pixels inside the reference penumbra (the `penumbra_rmse` population).
    #[serde(default)]
    pub penumbra_pixels: u64,
    /// Share (0..1) of valid pixels lit in one image and shadowed in the other (V thresholded at
    /// 1/2): against a point reference (`--reference point`) the hard shadow's mismatched pixels.
    #[serde(default)]
    pub mismatch_share: f64,
}

#[derive(Debug, thiserror::Error)]
pub enum MetricsError {
    #[error("image size {width}×{height} is empty or too large")]
    BadSize { width: u32, height: u32 },
    #[error("{what} has {got} entries, expected {expected} ({width}×{height})")]
    LengthMismatch {
        what: &'static str,
        got: usize,
        expected: usize,
        width: u32,
        height: u32,
    },
    #[error("{what} is {got_w}×{got_h}, expected {width}×{height}")]
    ImageSizeMismatch {
        what: &'static str,
        got_w: u32,
        got_h: u32,
        width: u32,
        height: u32,
    },
    #[error("reference value at pixel {index} is not finite")]
    NonFiniteReference { index: usize },
    #[error("no geometry pixel in the mask")]
    NoGeometry,
    #[error("every geometry pixel of the estimate is non-finite ({nan_count} pixels)")]
    NoValidPixels { nan_count: u64 },
    #[error("error-image scale must be finite and > 0, got {0}")]
    BadScale(f32),
    #[error("SSIM failed: {0}")]
    Ssim(String),
}

#[cfg(test)]
mod tests;
