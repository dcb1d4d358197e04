//! Decisions that hold still (docs/reuse.md §3): a method that hands its choice from one frame to
//! the next keeps it while the error it reads stays in a band around its target, so a choice does
//! not flicker on the error's noise from frame to frame. The one hook every such method asks:
//! `auto` passes its calibrated prediction of the frame's RMSE, `regions` the texel a kept map
//! gives against the texel its receivers need. A certified bound on the error can be passed in
//! place of an estimate without changing the callers.

/// The band's factor: a kept choice holds while its error is within [target / BAND, target × BAND].
/// (auto's `KEEP`, docs/error-estimate.md §6: the prediction moves by about this much from frame to
/// frame as the light moves.)
pub(crate) const BAND: f64 = 1.15;

/// Where a kept choice's error stands against the target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Standing {
    /// Below target / BAND: a cheaper choice may be taken.
    Below,
    /// Within the band: the choice holds.
    Within,
    /// Above target × BAND: the choice must rise.
    Above,
}

/// Where `error` stands against `target` (both in the same unit; a non-finite error is above).
pub(crate) fn standing(error: f64, target: f64) -> Standing {
    if !(error <= target * BAND) {
        Standing::Above
    } else if error < target / BAND {
        Standing::Below
    } else {
        Standing::Within
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_band_surrounds_the_target() {
        assert_eq!(standing(0.02, 0.02), Standing::Within);
        assert_eq!(standing(0.02 * 1.149, 0.02), Standing::Within);
        assert_eq!(standing(0.02 * 1.151, 0.02), Standing::Above);
        assert_eq!(standing(0.02 / 1.16, 0.02), Standing::Below);
        assert_eq!(standing(f64::NAN, 0.02), Standing::Above);
    }
}
