//! The sampling design: which pixels get the exact truth. K pixels are drawn independently with
//! probability q_p = a/N + (1 − a)·proxy_p/Σproxy over the N pixels of a subset (the geometry
//! pixels, or any class of them), so a truth-free proxy of where the error lies concentrates the
//! draws and the defensive uniform share a keeps every weight 1/(N q_p) at most 1/a where the
//! proxy is wrong (docs/certify.md §2).

use crate::{Error, Result};

/// The defensive uniform share: a weight never exceeds 1/a = 3.3.
pub const DEFENSIVE: f64 = 0.3;
/// How far the penumbra band reaches past the pixels with 0 < V < 1 or a neighbour of other V.
pub const BAND_DILATE: u32 = 2;

/// Draw probabilities over a subset of a frame's pixels.
#[derive(Clone, Debug)]
pub struct Design {
    /// The subset's pixels (frame indices), ascending.
    pixels: Vec<u32>,
    /// Cumulative q over `pixels`, ending at 1.
    cumulative: Vec<f64>,
    /// The largest weight 1/(N q_p) over the subset: the range of w for the per-frame bound.
    max_weight: f64,
    pub(crate) defensive: f64,
}

/// K drawn pixels: frame indices in draw order (repeats possible) and each draw's weight 1/(N q).
#[derive(Clone, Debug, PartialEq)]
pub struct Draw {
    pub(crate) pixels: Vec<u32>,
    pub(crate) weights: Vec<f64>,
}

impl Draw {
    /// Each pixel once, ascending: what the truth is traced at.
    pub(crate) fn unique(&self) -> Vec<u32> {
        let mut u = self.pixels.clone();
        u.sort_unstable();
        u.dedup();
        u
    }
}

impl Design {
    /// The design over the pixels where `subset` is true, drawing by `proxy` (any nonnegative
    /// scale; all zero means uniform) with the uniform share `defensive` ∈ (0, 1].
    pub fn new(subset: &[bool], proxy: &[f32], defensive: f64) -> Result<Design> {
        if subset.len() != proxy.len() {
            return Err(Error::Param(format!(
                "certify: a proxy of {} pixels for a frame of {}",
                proxy.len(),
                subset.len()
            )));
        }
        if !(defensive > 0.0 && defensive <= 1.0) {
            return Err(Error::Param(format!(
                "certify: the defensive share {defensive} is outside (0, 1]"
            )));
        }
        let pixels: Vec<u32> = (0..subset.len() as u32)
            .filter(|&i| subset[i as usize])
            .collect();
        if pixels.is_empty() {
            return Err(Error::Param("certify: no pixel to draw from".into()));
        }
        let n = pixels.len() as f64;
        let weight = |i: u32| f64::from(proxy[i as usize]).max(0.0);
        let total: f64 = pixels
            .iter()
            .map(|&i| weight(i))
            .filter(|w| w.is_finite())
            .sum();
        let a = if total > 0.0 { defensive } else { 1.0 };
        let mut cumulative = Vec::with_capacity(pixels.len());
        let (mut acc, mut max_weight) = (0.0, 0.0f64);
        for &i in &pixels {
            let w = weight(i);
            let share = if total > 0.0 && w.is_finite() {
                w / total
            } else {
                0.0
            };
            let q = a / n + (1.0 - a) * share;
            acc += q;
            cumulative.push(acc);
            max_weight = max_weight.max(1.0 / (n * q));
        }
        // Rounding: the last entry is 1.
        let last = cumulative.len() - 1;
        cumulative[last] = 1.0;
        Ok(Design {
            pixels,
            cumulative,
            max_weight,
            defensive: a,
        })
    }

    /// N: the pixels the bound is over.
    pub(crate) fn pixel_count(&self) -> usize {
        self.pixels.len()
    }

    /// The range of a draw's weighted squared error (e² ≤ 1).
    pub(crate) fn max_weight(&self) -> f64 {
        self.max_weight
    }

    /// q of the subset's `j`-th pixel.
    fn q(&self, j: usize) -> f64 {
        self.cumulative[j] - if j == 0 { 0.0 } else { self.cumulative[j - 1] }
    }

    /// K independent draws from a stream seeded by `seed` (the same seed, the same pixels).
    pub fn draw(&self, k: usize, seed: u64) -> Draw {
        let n = self.pixels.len() as f64;
        let mut state = seed ^ 0x6a09_e667_f3bc_c909;
        let (mut pixels, mut weights) = (Vec::with_capacity(k), Vec::with_capacity(k));
        for _ in 0..k {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let u = (splitmix(state) >> 11) as f64 / (1u64 << 53) as f64;
            let j = self
                .cumulative
                .partition_point(|&c| c <= u)
                .min(self.pixels.len() - 1);
            pixels.push(self.pixels[j]);
            weights.push(1.0 / (n * self.q(j)));
        }
        Draw { pixels, weights }
    }
}

fn splitmix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The penumbra band of V: 1 at subset pixels with 0 < V < 1 or a 4-neighbour in the subset of
/// other V (a hard edge), dilated by `dilate` pixels (a square), else 0.
pub fn band(v: &[f32], subset: &[bool], width: u32, height: u32, dilate: u32) -> Vec<f32> {
    let (w, h) = (width as usize, height as usize);
    let mut seed = vec![false; v.len()];
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            if !subset[i] {
                continue;
            }
            let soft = v[i] > 0.0 && v[i] < 1.0;
            let edge = [
                (x > 0).then(|| i - 1),
                (x + 1 < w).then(|| i + 1),
                (y > 0).then(|| i - w),
                (y + 1 < h).then(|| i + w),
            ]
            .into_iter()
            .flatten()
            .any(|j| subset[j] && v[j] != v[i]);
            seed[i] = soft || edge;
        }
    }
    // Dilation by a square: rows then columns.
    let d = dilate as usize;
    let mut rows = vec![false; v.len()];
    for y in 0..h {
        for x in 0..w {
            if seed[y * w + x] {
                for xx in x.saturating_sub(d)..=(x + d).min(w - 1) {
                    rows[y * w + xx] = true;
                }
            }
        }
    }
    let mut out = vec![0.0f32; v.len()];
    for y in 0..h {
        for x in 0..w {
            if rows[y * w + x] {
                for yy in y.saturating_sub(d)..=(y + d).min(h - 1) {
                    let i = yy * w + x;
                    if subset[i] {
                        out[i] = 1.0;
                    }
                }
            }
        }
    }
    out
}

/// The proxy from several parts: each scaled to sum 1 over the subset (a part that is zero
/// everywhere adds nothing), then added. Parts are truth-free: a candidate's band, the estimate's
/// per-pixel bound, the spread |V_a − V_b| between two candidates.
pub(crate) fn proxy(parts: &[&[f32]], subset: &[bool]) -> Vec<f32> {
    let mut out = vec![0.0f32; subset.len()];
    for part in parts {
        let total: f64 = part
            .iter()
            .zip(subset)
            .filter(|(x, s)| **s && x.is_finite())
            .map(|(x, _)| f64::from(x.max(0.0)))
            .sum();
        if total <= 0.0 {
            continue;
        }
        for ((o, x), s) in out.iter_mut().zip(part.iter()).zip(subset) {
            if *s && x.is_finite() {
                *o += (f64::from(x.max(0.0)) / total) as f32;
            }
        }
    }
    out
}

/// |a − b| per pixel (0 off the subset): where two candidates disagree, one of them errs.
pub(crate) fn spread(a: &[f32], b: &[f32], subset: &[bool]) -> Vec<f32> {
    a.iter()
        .zip(b)
        .zip(subset)
        .map(|((x, y), s)| if *s { (x - y).abs() } else { 0.0 })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_follow_q_and_weights_undo_it() {
        // 100 pixels, the proxy on the first 10: q = 0.3/100 + 0.7/10 there, 0.003 elsewhere.
        let subset = vec![true; 100];
        let proxy: Vec<f32> = (0..100).map(|i| if i < 10 { 1.0 } else { 0.0 }).collect();
        let d = Design::new(&subset, &proxy, 0.3).unwrap();
        assert!((d.max_weight() - 1.0 / 0.3).abs() < 1e-9);
        let draw = d.draw(20000, 5);
        let hot = draw.pixels.iter().filter(|&&p| p < 10).count() as f64 / 20000.0;
        assert!((hot - 0.73).abs() < 0.015, "{hot}");
        // The weights' mean over the draws estimates the mean of 1 over the pixels: 1.
        let mean: f64 = draw.weights.iter().sum::<f64>() / 20000.0;
        assert!((mean - 1.0).abs() < 0.05, "{mean}");
        assert_eq!(d.draw(50, 9), d.draw(50, 9));
        assert_ne!(d.draw(50, 9), d.draw(50, 10));
    }

    #[test]
    fn a_subset_is_drawn_alone_and_a_zero_proxy_is_uniform() {
        let subset: Vec<bool> = (0..50).map(|i| i % 2 == 0).collect();
        let d = Design::new(&subset, &[0.0; 50], 0.3).unwrap();
        assert_eq!(d.pixel_count(), 25);
        assert_eq!(d.defensive, 1.0);
        assert!(d.draw(500, 1).pixels.iter().all(|p| p % 2 == 0));
        assert!((d.max_weight() - 1.0).abs() < 1e-12);
        assert!(Design::new(&[false; 4], &[1.0; 4], 0.3).is_err());
        assert!(Design::new(&[true; 4], &[1.0; 3], 0.3).is_err());
        assert!(Design::new(&[true; 4], &[1.0; 4], 0.0).is_err());
    }

    #[test]
    fn the_band_holds_soft_pixels_and_hard_edges_dilated() {
        // A 9x1 row: lit, lit, lit, lit, dark, dark, ...: an edge between 3 and 4.
        let v = [1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0f32];
        let all = [true; 9];
        assert_eq!(
            band(&v, &all, 9, 1, 0),
            [0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0]
        );
        assert_eq!(
            band(&v, &all, 9, 1, 2),
            [0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0]
        );
        let soft = [1.0, 1.0, 0.5, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0f32];
        assert_eq!(band(&soft, &all, 9, 1, 0)[1..4], [1.0, 1.0, 1.0]);
        // Pixels off the subset are neither edges nor in the band.
        let mut some = all;
        some[4] = false;
        assert_eq!(band(&v, &some, 9, 1, 0), [0.0; 9]);
    }

    #[test]
    fn proxy_parts_count_alike_whatever_their_scale() {
        let subset = [true, true, true, false];
        let a = [1.0, 0.0, 0.0, 9.0f32];
        let b = [0.0, 0.0, 100.0, 0.0f32];
        assert_eq!(proxy(&[&a, &b], &subset), [1.0, 0.0, 1.0, 0.0]);
        assert_eq!(spread(&a, &b, &subset), [1.0, 0.0, 100.0, 0.0]);
    }
}
