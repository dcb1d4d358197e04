//! The error estimate without a reference (docs/error-estimate.md): from the per-pixel sums of
//! the `estimate` stage, the predicted RMSE of V split into the light-sampling part and the maps'
//! part, and a per-pixel bound on |V − V_true|.

use super::Layout;
use crate::stages::estimate::Sums;
use crate::Result;

/// RMS error of the full grid per unit of RMS half-set difference, by layout (§2): the centred
/// grid's from the median over the 18 area-light scenes at n = 5, the others' from `default`,
/// `cows` and `disk-bar` (docs/error-estimate.md §2, §5).
pub(crate) fn sampling_scale(layout: Layout) -> f64 {
    match layout {
        Layout::Centred => 0.142,
        Layout::Lattice => 0.30,
        Layout::Jittered => 0.12,
    }
}

/// The per-pixel bound is this many predicted standard errors …
pub(crate) const BOUND_SIGMAS: f32 = 3.0;
/// … plus this floor: the continuous reference's own error and the maps' error that neither
/// term sees (§4).
pub const BOUND_FLOOR: f32 = 0.01;

/// Sample i's signed weights in the two half-set differences: +1/|even| for an even column
/// (row) of the n×n grid, −1/|odd| for an odd one. A point light's sample is `faces` consecutive
/// maps, each with its sample's weights. n = 1 has no halves: all zero.
pub(crate) fn split_weights(n: u32, faces: usize) -> Vec<[f32; 2]> {
    let even = n.div_ceil(2) as f32 * n as f32;
    let odd = (n / 2) as f32 * n as f32;
    let signed = |i: u32| if i % 2 == 0 { 1.0 / even } else { -1.0 / odd };
    (0..n * n)
        .flat_map(|k| {
            let w = if n < 2 {
                [0.0, 0.0]
            } else {
                [signed(k % n), signed(k / n)]
            };
            std::iter::repeat_n(w, faces)
        })
        .collect()
}

/// How much larger a half-set difference's variance is than the full grid's mean's, for errors
/// independent from sample to sample: n²·(1/|even| + 1/|odd|) per axis (4.5 at n = 3, 4 for even
/// n). 0 where there are no halves (n = 1).
pub(crate) fn averaging_ratio(n: u32) -> f64 {
    let (even, odd) = (n.div_ceil(2) * n, (n / 2) * n);
    if odd == 0 {
        return 0.0;
    }
    (n * n) as f64 * (1.0 / even as f64 + 1.0 / odd as f64)
}

/// The frame's predicted errors (RMS over geometry pixels, as the measured RMSE).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Prediction {
    pub predicted_rmse: f64,
    pub predicted_sampling: f64,
    pub predicted_map: f64,
    /// The maps' part's two terms: quantization (RMS Q) and bias (RMS B), m² = Q² + B².
    pub predicted_quantization: f64,
    pub predicted_bias: f64,
    /// The part of the maps' error that averages out over samples (RMS, at most `predicted_map`):
    /// from the half-set differences of Q and B. At n'² samples the maps' error is predicted as
    /// sqrt(m² − a² · (1 − n²/n'²)) (§3, §6).
    pub predicted_map_averaging: f64,
}

/// Per pixel: predicted sampling and map error (root of the mean square over pixels gives the
/// frame's figures) from the sums (x, y: half-set differences; z: quantization; w: bias), and
/// the square of the maps' part that averages over samples, from Q's and B's half-set
/// differences (`ratio`: `averaging_ratio`; two axes, so divided by twice it).
pub(crate) fn pixel_terms(sum: Sums, layout: Layout, ratio: f64) -> (f64, f64, f64) {
    let c = sampling_scale(layout);
    let x = sum.map(|v| v as f64);
    let (dx, dy, q, b) = (x[0], x[1], x[2], x[3]);
    let halves = x[4] * x[4] + x[5] * x[5] + x[6] * x[6] + x[7] * x[7];
    let averaging = if ratio > 0.0 {
        halves / (2.0 * ratio)
    } else {
        0.0
    };
    (
        c * (dx * dx + dy * dy).sqrt(),
        (q * q + b * b).sqrt(),
        averaging,
    )
}

/// The frame's prediction and each pixel's bound (0 off geometry).
/// `side`: the grid's n (`averaging_ratio`).
pub fn predict(
    sums: &[Sums],
    geometry: &[bool],
    layout: Layout,
    side: u32,
) -> Result<(Prediction, Vec<f32>)> {
    if sums.len() != geometry.len() {
        return Err(crate::Error::Limit(format!(
            "estimate: {} sums for {} pixels",
            sums.len(),
            geometry.len()
        )));
    }
    let ratio = averaging_ratio(side);
    let (mut s2, mut m2, mut q2, mut a2, mut pixels) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0usize);
    let mut bound = vec![0.0f32; sums.len()];
    for (i, sum) in sums.iter().enumerate().filter(|(i, _)| geometry[*i]) {
        let (s, m, a) = pixel_terms(*sum, layout, ratio);
        s2 += s * s;
        m2 += m * m;
        a2 += a;
        q2 += (sum[2] as f64).powi(2);
        pixels += 1;
        bound[i] = BOUND_SIGMAS * (s * s + m * m).sqrt() as f32 + BOUND_FLOOR;
    }
    let n = pixels.max(1) as f64;
    let (sampling, map) = ((s2 / n).sqrt(), (m2 / n).sqrt());
    let quantization = (q2 / n).sqrt();
    let p = Prediction {
        predicted_rmse: (sampling * sampling + map * map).sqrt(),
        predicted_sampling: sampling,
        predicted_map: map,
        predicted_quantization: quantization,
        predicted_bias: (map * map - quantization * quantization).max(0.0).sqrt(),
        predicted_map_averaging: (a2 / n).sqrt().min(map),
    };
    Ok((p, bound))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halves_balance() {
        for n in [2u32, 3, 5, 8] {
            let w = split_weights(n, 1);
            assert_eq!(w.len(), (n * n) as usize);
            for axis in 0..2 {
                let sum: f32 = w.iter().map(|x| x[axis]).sum();
                assert!(
                    sum.abs() < 1e-5,
                    "n = {n}: the halves' weights cancel on a constant V ({sum})"
                );
                let pos: f32 = w.iter().map(|x| x[axis].max(0.0)).sum();
                assert!(
                    (pos - 1.0).abs() < 1e-5,
                    "n = {n}: each half is a mean ({pos})"
                );
            }
        }
        assert_eq!(split_weights(1, 6), vec![[0.0, 0.0]; 6]);
        let cube = split_weights(2, 6);
        assert_eq!(cube.len(), 24);
        assert_eq!(
            cube[5], cube[0],
            "the six faces of a point's sample share its weights"
        );
        assert_eq!(
            cube[6],
            [-0.5, 0.5],
            "sample 1 is column 1, row 0 of the 2×2 grid"
        );
    }

    #[test]
    fn prediction_adds_the_terms_in_quadrature() {
        let sums = vec![
            [0.2, 0.0, 0.03, 0.04, 0.0, 0.0, 0.0, 0.0],
            [0.0; 8],
            [9.0; 8],
        ];
        let geometry = vec![true, true, false];
        let (p, bound) = predict(&sums, &geometry, Layout::Centred, 4).unwrap();
        let s = sampling_scale(Layout::Centred) * 0.2;
        assert!((p.predicted_sampling - (s * s / 2.0).sqrt()).abs() < 1e-7);
        assert!((p.predicted_map - (0.05f64 * 0.05 / 2.0).sqrt()).abs() < 1e-7);
        // Its two terms: RMS Q = 0.03/√2, RMS B = 0.04/√2.
        assert!((p.predicted_quantization - 0.03 / 2f64.sqrt()).abs() < 1e-7);
        assert!((p.predicted_bias - 0.04 / 2f64.sqrt()).abs() < 1e-7);
        assert!(
            (p.predicted_rmse - (p.predicted_sampling.powi(2) + p.predicted_map.powi(2)).sqrt())
                .abs()
                < 1e-12
        );
        assert_eq!(bound[2], 0.0, "no bound off geometry");
        assert_eq!(bound[1], BOUND_FLOOR);
        assert!(
            (bound[0] - (BOUND_SIGMAS * (s * s + 0.0025).sqrt() as f32 + BOUND_FLOOR)).abs() < 1e-6
        );
        assert_eq!(
            p.predicted_map_averaging, 0.0,
            "halves that agree: nothing averages"
        );
        assert!(predict(&sums, &[true], Layout::Centred, 4).is_err());
    }

    #[test]
    fn the_averaging_part_is_the_halves_difference_over_the_ratio() {
        assert_eq!(averaging_ratio(1), 0.0);
        assert_eq!(averaging_ratio(4), 4.0);
        assert!(
            (averaging_ratio(3) - 4.5).abs() < 1e-12,
            "n = 3: 9·(1/6 + 1/3)"
        );
        // Q's halves differ by 0.06 in columns and rows, B's agree: a² = (2 · 0.06²) / (2 · 4).
        let sums = vec![
            [0.0, 0.0, 0.05, 0.0, 0.06, 0.06, 0.0, 0.0],
            [0.0, 0.0, 0.05, 0.0, 0.06, 0.06, 0.0, 0.0],
        ];
        let (p, _) = predict(&sums, &[true, true], Layout::Centred, 4).unwrap();
        assert!(
            (p.predicted_map_averaging - 0.03).abs() < 1e-7,
            "{}",
            p.predicted_map_averaging
        );
        assert!((p.predicted_map - 0.05).abs() < 1e-7);
        // Capped at the maps' error: halves far apart with a small mean.
        let sums = vec![[0.0, 0.0, 0.01, 0.0, 0.5, 0.5, 0.0, 0.0]];
        let (p, _) = predict(&sums, &[true], Layout::Centred, 4).unwrap();
        assert_eq!(p.predicted_map_averaging, p.predicted_map);
    }
}
