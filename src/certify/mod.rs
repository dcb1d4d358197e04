//! A certified error: the exact truth at a few thousand pixels and a one-sided bound on the
//! frame's RMSE of V at confidence 1 − δ, by construction rather than by a fitted prediction
//! (docs/certify.md).
//!
//! Three steps, each usable alone:
//! 1. [`design::Design`]: draw probabilities over a subset of the frame's pixels (the geometry
//!    pixels, or any class of them: a mask) from a truth-free proxy with a defensive uniform
//!    share; [`design::Design::draw`] draws K pixels.
//! 2. [`truth::TruthTracer`]: the reference's integrator at those pixels on the GPU
//!    (`truth_trace`), or any other source of the same values ([`Sampled::from_values`]: a
//!    full reference already at hand).
//! 3. [`certificate`]: for any candidate V, the sampled MSE and the bounds; one [`Sampled`]
//!    serves every candidate of a frame, since the draws do not depend on the candidate.
//!
//! ```no_run
//! # fn f(ctx: &penumbra::research::gpu::GpuContext, scene: &penumbra::research::scene::Scene, g: &penumbra::research::render::gbuffer::GBufferCpu, v: &[f32], class: &[bool]) -> penumbra::Result<()> {
//! use penumbra::research::certify::{self, design, truth::TruthTracer, Options};
//! let tracer = TruthTracer::new(ctx, scene)?;
//! // The bound over one class of pixels (a per-region decision): its mask is the subset, and the
//! // candidate's own band the proxy.
//! let proxy = design::band(v, class, g.width, g.height, design::BAND_DILATE);
//! let design = design::Design::new(class, &proxy, design::DEFENSIVE)?;
//! let options = Options::default();
//! let sampled = certify::sample(ctx, &tracer, g, &design, &options)?;
//! let c = certify::certificate(v, &sampled, &design, options.delta, certify::bound::BoundKind::Calibrated);
//! println!("RMSE ≤ {:.4} at {:.0}% over the class", c.bound, 100.0 * (1.0 - c.delta));
//! # Ok(()) }
//! ```

pub(crate) mod bound;
pub(crate) mod design;
pub(crate) mod truth;

use crate::gpu::GpuContext;
use crate::render::gbuffer::GBufferCpu;
use crate::{Error, Result};
use bound::BoundKind;
use design::{Design, Draw};
use truth::{TruthCounts, TruthTracer};

/// K, the drawn pixels, by default.
pub(crate) const DEFAULT_PIXELS: usize = 2048;
/// δ: the bound holds with probability at least 1 − δ.
pub const DEFAULT_DELTA: f64 = 0.05;

/// How many pixels, at what confidence, from which seed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    pub pixels: usize,
    pub delta: f64,
    pub seed: u64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            pixels: DEFAULT_PIXELS,
            delta: DEFAULT_DELTA,
            seed: 0x5eed_0055,
        }
    }
}

/// The checks every caller words for its own flags: K in 1..=N, δ in (0, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OptionsError {
    NoPixels,
    MorePixelsThanGeometry { pixels: usize, geometry: usize },
    Delta(f64),
}

impl Options {
    /// K of 0, K above the frame's `geometry` pixels, δ outside (0, 1).
    pub fn check(&self, geometry: usize) -> std::result::Result<(), OptionsError> {
        if self.pixels == 0 {
            return Err(OptionsError::NoPixels);
        }
        if self.pixels > geometry {
            return Err(OptionsError::MorePixelsThanGeometry {
                pixels: self.pixels,
                geometry,
            });
        }
        if !(self.delta > 0.0 && self.delta < 1.0) {
            return Err(OptionsError::Delta(self.delta));
        }
        Ok(())
    }
}

impl std::fmt::Display for OptionsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            OptionsError::NoPixels => write!(
                f,
                "pixels = 0: draw at least one pixel (2048 is the default)"
            ),
            OptionsError::MorePixelsThanGeometry { pixels, geometry } => write!(
                f,
                "pixels = {pixels} is more than the frame's {geometry} geometry pixels"
            ),
            OptionsError::Delta(d) => write!(
                f,
                "delta = {d} is outside (0, 1): the bound holds with probability 1 − delta"
            ),
        }
    }
}

/// The exact truth at a draw's pixels.
#[derive(Clone, Debug)]
pub struct Sampled {
    pub(crate) draw: Draw,
    /// The drawn pixels once each, ascending, and V there.
    pub(crate) unique: Vec<u32>,
    pub(crate) truth: Vec<f32>,
    /// A second estimate of the truth, independent of `truth`, where both are traced with fewer
    /// samples than the reference's (`truth::paired`): the product of the two errors is then
    /// unbiased for e² (see [`weighted_errors`]).
    pub(crate) second: Option<Vec<f32>>,
    /// The trace's rays and ties, and its wall clock (None: the values came from elsewhere).
    pub(crate) trace: Option<TraceFigures>,
}

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub(crate) struct TraceFigures {
    pub(crate) rays: u64,
    pub(crate) ties: u64,
    pub(crate) ms: f64,
    pub(crate) samples_per_pixel: u32,
}

impl Sampled {
    /// The truth from values already known per frame pixel (a full reference): the study's
    /// shortcut, equal to the traced truth at those pixels (lab/tests/truth_trace.rs).
    pub fn from_values(draw: Draw, values: &[f32]) -> Sampled {
        let unique = draw.unique();
        let truth = unique.iter().map(|&p| values[p as usize]).collect();
        Sampled {
            draw,
            unique,
            truth,
            second: None,
            trace: None,
        }
    }

    /// Two independent estimates of the truth per frame pixel (`truth::paired`), from which the
    /// draws' squared errors are estimated without the estimates' own noise.
    pub(crate) fn from_pair(draw: Draw, first: &[f32], second: &[f32]) -> Sampled {
        let mut s = Sampled::from_values(draw, first);
        s.second = Some(s.unique.iter().map(|&p| second[p as usize]).collect());
        s
    }

    fn from_counts(draw: Draw, unique: Vec<u32>, counts: &TruthCounts) -> Sampled {
        let truth = (0..unique.len()).map(|i| counts.visibility(i)).collect();
        let trace = TraceFigures {
            rays: counts.rays(),
            ties: counts.ties(),
            ms: counts.ms,
            samples_per_pixel: counts.samples_per_pixel,
        };
        Sampled {
            draw,
            unique,
            truth,
            second: None,
            trace: Some(trace),
        }
    }

    /// The estimate of e² at a drawn pixel for a candidate's value `v` there: (v − t)² with the
    /// reference's truth; (v − t₁)(v − t₂) with two independent estimates, whose expectation is
    /// (v − t)² exactly (E[t₁] = E[t₂] = t, independent), where (v − t₁)² would be biased up by
    /// t₁'s variance. It can be negative; its mean over the draws is what is unbiased.
    pub(crate) fn squared_error(&self, pixel: u32, v: f32) -> f64 {
        let i = self.unique.binary_search(&pixel).expect("a drawn pixel");
        let v = f64::from(v.clamp(0.0, 1.0));
        let e = v - f64::from(self.truth[i]);
        match &self.second {
            None => e * e,
            Some(second) => e * (v - f64::from(second[i])),
        }
    }
}

/// Draws `options.pixels` pixels by `design` and traces the reference's 32 × 32 samples there.
pub fn sample(
    ctx: &GpuContext,
    tracer: &TruthTracer,
    g: &GBufferCpu,
    design: &Design,
    options: &Options,
) -> Result<Sampled> {
    if design.pixel_count() == 0 {
        return Err(Error::Param("certify: no pixel to draw from".into()));
    }
    let draw = design.draw(options.pixels, options.seed);
    let unique = draw.unique();
    let points: Vec<_> = unique.iter().map(|&p| truth::point_of(g, p)).collect();
    let counts = tracer.trace(ctx, &truth::REFERENCE_SAMPLES, &points, &|_| {})?;
    Ok(Sampled::from_counts(draw, unique, &counts))
}

/// What a bound says of one candidate, as run.json keeps it (`certify`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Certificate {
    /// K: pixels drawn (with repeats), and how many distinct pixels were traced.
    pub pixels: usize,
    pub unique_pixels: usize,
    pub delta: f64,
    /// sqrt of the sampled MSE (unbiased for the MSE): the estimate, not a bound.
    pub sampled_rmse: f64,
    /// The bound the record stands by, and which it is.
    pub bound: f64,
    pub bound_kind: BoundKind,
    /// Every bound, whichever is `bound`: distribution-free, calibrated, and plain Student t.
    pub per_frame_bound: f64,
    pub(crate) calibrated_bound: f64,
    pub student_t_bound: f64,
    /// The calibrated bound's stretch of the t bound.
    pub(crate) stretch: f64,
    /// N: the pixels the bound is over; the design's uniform share and largest weight.
    pub(crate) subset_pixels: usize,
    pub(crate) defensive: f64,
    pub(crate) max_weight: f64,
}

/// The weighted squared errors of `v` at the draws: e² / (N q) each, in draw order.
pub(crate) fn weighted_errors(v: &[f32], sampled: &Sampled) -> Vec<f64> {
    sampled
        .draw
        .pixels
        .iter()
        .zip(&sampled.draw.weights)
        .map(|(&p, &w)| sampled.squared_error(p, v[p as usize]) * w)
        .collect()
}

/// The bounds on `v`'s RMSE over `design`'s subset from `sampled`, `kind` the one it stands by.
pub fn certificate(
    v: &[f32],
    sampled: &Sampled,
    design: &Design,
    delta: f64,
    kind: BoundKind,
) -> Certificate {
    let w = weighted_errors(v, sampled);
    let (mean, _) = bound::mean_sd(&w);
    // The betting bound needs w in [0, range]: a paired estimate's negative terms are raised to
    // 0, which only moves its mean up (the safe side).
    let nonnegative: Vec<f64> = w.iter().map(|x| x.max(0.0)).collect();
    let per_frame = bound::betting(&nonnegative, design.max_weight(), delta).sqrt();
    let t = bound::student_t(&w, delta).max(0.0).sqrt();
    let calibrated = bound::calibrated(&w, delta);
    Certificate {
        pixels: sampled.draw.pixels.len(),
        unique_pixels: sampled.unique.len(),
        delta,
        sampled_rmse: mean.max(0.0).sqrt(),
        bound: match kind {
            BoundKind::PerFrame => per_frame,
            BoundKind::Calibrated => calibrated,
        },
        bound_kind: kind,
        per_frame_bound: per_frame,
        calibrated_bound: calibrated,
        student_t_bound: t,
        stretch: bound::STRETCH,
        subset_pixels: design.pixel_count(),
        defensive: design.defensive,
        max_weight: design.max_weight(),
    }
}

/// The bound a decision against target `t` stands by: the per-frame one where even its floor
/// (no error seen in K draws) is at most half of t, so it can certify t; the calibrated one
/// elsewhere. Decided from t, K, δ and the design alone, never from the draws.
pub(crate) fn kind_for_target(t: f64, pixels: usize, delta: f64, max_weight: f64) -> BoundKind {
    let floor = bound::betting(&vec![0.0; pixels], max_weight, delta).sqrt();
    if floor <= 0.5 * t {
        BoundKind::PerFrame
    } else {
        BoundKind::Calibrated
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic uniform in [0, 1) (SplitMix64).
    struct Uniform(u64);
    impl Uniform {
        fn next(&mut self) -> f32 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    /// An estimate of a penumbra pixel's V from `samples` light points, each lit with probability
    /// `truth`.
    fn estimate(rng: &mut Uniform, truth: f32, samples: u32) -> f32 {
        (0..samples).filter(|_| rng.next() < truth).count() as f32 / samples as f32
    }

    #[test]
    fn a_paired_truth_is_unbiased_where_one_estimate_is_not() {
        // 4,000 pixels of true V 0.3 under a candidate's 0.4: e² = 0.01. Each pixel's truth is
        // estimated from 16 points, whose own variance (0.3 · 0.7 / 16 = 0.0131) a single
        // estimate adds to e²; the product of two independent errors does not.
        let (n, truth, v, samples) = (4000usize, 0.3f32, 0.4f32, 16);
        let mut rng = Uniform(7);
        let first: Vec<f32> = (0..n).map(|_| estimate(&mut rng, truth, samples)).collect();
        let second: Vec<f32> = (0..n).map(|_| estimate(&mut rng, truth, samples)).collect();
        let draw = Draw {
            pixels: (0..n as u32).collect(),
            weights: vec![1.0; n],
        };
        let candidate = vec![v; n];
        let single = weighted_errors(&candidate, &Sampled::from_values(draw.clone(), &first));
        let paired = weighted_errors(&candidate, &Sampled::from_pair(draw, &first, &second));
        let e2 = f64::from((v - truth).powi(2));
        let var = f64::from(truth * (1.0 - truth)) / f64::from(samples);
        let (single_mean, single_sd) = bound::mean_sd(&single);
        let (paired_mean, paired_sd) = bound::mean_sd(&paired);
        let se = |sd: f64| sd / (n as f64).sqrt();
        println!(
            "e² {e2:.5}: single {single_mean:.5} ± {:.5}, paired {paired_mean:.5} ± {:.5}",
            se(single_sd),
            se(paired_sd)
        );
        // The single estimate sits at e² + Var, the paired at e², each within 4 standard errors.
        assert!((single_mean - (e2 + var)).abs() < 4.0 * se(single_sd));
        assert!((paired_mean - e2).abs() < 4.0 * se(paired_sd));
        assert!(
            single_mean - e2 > 8.0 * se(single_sd),
            "the single estimate's bias is seen"
        );
        // Some products are negative: the pair's terms are estimates, not squares.
        assert!(paired.iter().any(|&w| w < 0.0));
        // Where both estimates are the truth the pair is the square.
        let exact = vec![truth; n];
        let draw = Draw {
            pixels: (0..n as u32).collect(),
            weights: vec![1.0; n],
        };
        let both = weighted_errors(&candidate, &Sampled::from_pair(draw, &exact, &exact));
        assert!(both.iter().all(|&w| (w - e2).abs() < 1e-9));
    }

    #[test]
    fn a_paired_certificate_keeps_its_bounds_in_range() {
        // A candidate equal to the truth's mean: the products are centred on 0, many negative.
        let n = 500usize;
        let mut rng = Uniform(11);
        let first: Vec<f32> = (0..n).map(|_| estimate(&mut rng, 0.5, 4)).collect();
        let second: Vec<f32> = (0..n).map(|_| estimate(&mut rng, 0.5, 4)).collect();
        let mask = vec![true; n];
        let design = Design::new(&mask, &vec![0.0; n], design::DEFENSIVE).unwrap();
        let draw = design.draw(200, 3);
        let sampled = Sampled::from_pair(draw, &first, &second);
        let c = certificate(
            &vec![0.5; n],
            &sampled,
            &design,
            0.05,
            BoundKind::Calibrated,
        );
        // The estimate is a root of a mean clamped at 0, the bounds finite and at least it.
        assert!(c.sampled_rmse.is_finite() && c.sampled_rmse >= 0.0);
        assert!(c.per_frame_bound.is_finite() && c.per_frame_bound >= c.sampled_rmse);
        assert!(c.student_t_bound.is_finite() && c.student_t_bound >= c.sampled_rmse);
        assert!(c.bound > 0.0 && c.bound < 1.0, "bound {}", c.bound);
    }
}
