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
            trace: None,
        }
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
            trace: Some(trace),
        }
    }

    /// V_true at a drawn pixel.
    pub(crate) fn truth_at(&self, pixel: u32) -> f32 {
        self.truth[self.unique.binary_search(&pixel).expect("a drawn pixel")]
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
        .map(|(&p, &w)| {
            let e = f64::from(v[p as usize].clamp(0.0, 1.0)) - f64::from(sampled.truth_at(p));
            e * e * w
        })
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
    let per_frame = bound::betting(&w, design.max_weight(), delta).sqrt();
    let t = bound::student_t(&w, delta).max(0.0).sqrt();
    let calibrated = bound::calibrated(&w, delta);
    Certificate {
        pixels: sampled.draw.pixels.len(),
        unique_pixels: sampled.unique.len(),
        delta,
        sampled_rmse: mean.sqrt(),
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
