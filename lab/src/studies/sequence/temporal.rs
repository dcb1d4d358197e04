//! Temporal metrics of a sequence (docs/sequence.md): how well a method's frame-to-frame change of
//! V follows the reference's, and how many pixels pop. Both are taken over pixels that are geometry
//! in both frames.

use serde::{Deserialize, Serialize};

/// A pixel pops when V changes by more than this between two frames …
pub const POP_CHANGE: f32 = 1.0 / 32.0;
/// … while the reference changes by less than this.
pub const POP_STILL: f32 = 1.0 / 256.0;

/// The temporal figures of one frame against the frame before it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct FramePair {
    /// RMSE of (V_t − V_{t−1}) − (R_t − R_{t−1}).
    pub temporal_rmse: f64,
    /// Share (0..1) of the pixels that pop.
    pub popping_share: f64,
    /// Pixels that pop.
    pub popping_pixels: u64,
    /// Pixels both frames cover with geometry: the population of both figures.
    pub pixels: u64,
    /// Σ of the squared change error, kept so sequence totals weigh every pixel once.
    pub sum_sq: f64,
}

/// Compares frame t with frame t−1 of the method (`v`) and of the reference (`r`). `geometry`
/// masks are per frame (a moving camera changes them); slices are row-major and equally long.
pub fn frame_pair(
    v_prev: &[f32],
    v: &[f32],
    r_prev: &[f32],
    r: &[f32],
    geo_prev: &[bool],
    geo: &[bool],
) -> FramePair {
    let n = v.len();
    assert!(
        [
            v_prev.len(),
            r_prev.len(),
            r.len(),
            geo_prev.len(),
            geo.len()
        ]
        .iter()
        .all(|&l| l == n),
        "temporal metrics need equally sized frames"
    );
    let (mut sum_sq, mut pixels, mut pops) = (0.0f64, 0u64, 0u64);
    for i in 0..n {
        if !(geo[i] && geo_prev[i]) {
            continue;
        }
        let dv = v[i] - v_prev[i];
        let dr = r[i] - r_prev[i];
        let e = f64::from(dv) - f64::from(dr);
        sum_sq += e * e;
        pixels += 1;
        if dv.abs() > POP_CHANGE && dr.abs() < POP_STILL {
            pops += 1;
        }
    }
    let share = |k: u64| {
        if pixels == 0 {
            0.0
        } else {
            k as f64 / pixels as f64
        }
    };
    FramePair {
        temporal_rmse: if pixels == 0 {
            0.0
        } else {
            (sum_sq / pixels as f64).sqrt()
        },
        popping_share: share(pops),
        popping_pixels: pops,
        pixels,
        sum_sq,
    }
}

/// The sequence's figures: every frame pair's pixels weighed once.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct SequenceTemporal {
    /// √(Σ squared change error / Σ pixels) over all frame pairs.
    pub temporal_rmse: f64,
    /// Σ popping pixels / Σ pixels over all frame pairs.
    pub popping_share: f64,
    pub popping_pixels: u64,
    pub pixels: u64,
}

pub fn sequence(pairs: &[FramePair]) -> SequenceTemporal {
    let pixels: u64 = pairs.iter().map(|p| p.pixels).sum();
    let pops: u64 = pairs.iter().map(|p| p.popping_pixels).sum();
    let sum_sq: f64 = pairs.iter().map(|p| p.sum_sq).sum();
    if pixels == 0 {
        return SequenceTemporal::default();
    }
    SequenceTemporal {
        temporal_rmse: (sum_sq / pixels as f64).sqrt(),
        popping_share: pops as f64 / pixels as f64,
        popping_pixels: pops,
        pixels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_method_that_follows_the_reference_exactly_has_no_temporal_error() {
        let r0 = [0.2, 0.5, 1.0, 0.0];
        let r1 = [0.3, 0.4, 1.0, 0.0];
        // V is off by a constant 0.1 in both frames: per-frame error, no temporal error.
        let v0 = r0.map(|x: f32| x + 0.1);
        let v1 = r1.map(|x: f32| x + 0.1);
        let geo = [true; 4];
        let p = frame_pair(&v0, &v1, &r0, &r1, &geo, &geo);
        assert!(p.temporal_rmse < 1e-7, "{p:?}");
        assert_eq!((p.popping_pixels, p.pixels), (0, 4));
    }

    #[test]
    fn known_change_error_and_pops() {
        // Four geometry pixels, the reference still everywhere.
        // Changes of V: 0.5, 0.02, −0.25, 0 → errors the same; pops: 0.5 and −0.25 (> 1/32).
        let r = [0.5f32; 4];
        let v0 = [0.0, 0.5, 0.75, 0.5];
        let v1 = [0.5, 0.52, 0.5, 0.5];
        let geo = [true; 4];
        let p = frame_pair(&v0, &v1, &r, &r, &geo, &geo);
        let expect = ((0.25f64 + 0.0004 + 0.0625) / 4.0).sqrt();
        assert!(
            (p.temporal_rmse - expect).abs() < 1e-6,
            "{} vs {expect}",
            p.temporal_rmse
        );
        assert_eq!((p.popping_pixels, p.pixels), (2, 4));
        assert_eq!(p.popping_share, 0.5);
    }

    #[test]
    fn a_change_the_reference_shares_is_no_pop() {
        // V jumps by 0.5 at both pixels; the reference moves by 0.5 at the first (no pop, no error)
        // and by 0.0035 (< 1/256) at the second (a pop, error 0.4965).
        let v0 = [0.0f32, 0.0];
        let v1 = [0.5f32, 0.5];
        let r0 = [0.0f32, 0.0];
        let r1 = [0.5f32, 0.0035];
        let geo = [true; 2];
        let p = frame_pair(&v0, &v1, &r0, &r1, &geo, &geo);
        assert_eq!(p.popping_pixels, 1);
        let expect = (0.4965f64 * 0.4965 / 2.0).sqrt();
        assert!(
            (p.temporal_rmse - expect).abs() < 1e-6,
            "{} vs {expect}",
            p.temporal_rmse
        );
    }

    #[test]
    fn only_pixels_covered_in_both_frames_count() {
        let v0 = [0.0f32, 0.0, 0.0];
        let v1 = [1.0f32, 1.0, 1.0];
        let r = [0.0f32; 3];
        // Pixel 0 is background in frame t−1, pixel 1 in frame t: only pixel 2 counts.
        let p = frame_pair(&v0, &v1, &r, &r, &[false, true, true], &[true, false, true]);
        assert_eq!((p.pixels, p.popping_pixels), (1, 1));
        assert_eq!(p.temporal_rmse, 1.0);
    }

    #[test]
    fn sequence_weighs_every_pixel_once() {
        let a = FramePair {
            temporal_rmse: 0.0,
            popping_share: 0.0,
            popping_pixels: 0,
            pixels: 3,
            sum_sq: 0.0,
        };
        let b = FramePair {
            temporal_rmse: 1.0,
            popping_share: 1.0,
            popping_pixels: 1,
            pixels: 1,
            sum_sq: 1.0,
        };
        let s = sequence(&[a, b]);
        assert_eq!((s.pixels, s.popping_pixels), (4, 1));
        assert_eq!(s.popping_share, 0.25);
        assert_eq!(s.temporal_rmse, 0.5);
        assert_eq!(sequence(&[]), SequenceTemporal::default());
    }
}
