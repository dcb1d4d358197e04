//! `regions`' error budget (docs/regions.md, "The target's two parts"): the frame's squared
//! target splits evenly between the light samples and the maps' texels. The samples' half is the
//! `classify` kernel's target; the maps' half sets the texel density, from a model of the maps'
//! error that reads only what `measure` kept per region.

use crate::stages::regions::{unordered, RegionsParams, REGION_WORDS};
use crate::stages::twin::regions::{samples_of, total};

/// The samples' share of the target: T_s = T/√2, so T_s² + T_m² = T² with T_m = T_s.
pub const SAMPLING_SHARE: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// One penumbra region's share of the frame's edge weight E, so that at D texels per pixel
/// footprint the maps' error is m² = E / (12 D N) (docs/regions.md). `together` where its n
/// columns of samples' edges fall within one texel of each other (their maps' errors add as
/// one map's), `apart` from the density `apart_from` up, where they lie a texel or more apart
/// and average over the columns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeTerm {
    pub apart_from: f64,
    pub together: f64,
    pub apart: f64,
}

impl EdgeTerm {
    /// This region's weight at `density` texels per footprint.
    pub fn at(&self, density: f64) -> f64 {
        if density >= self.apart_from {
            self.apart
        } else {
            self.together
        }
    }
}

/// Each penumbra region's [`EdgeTerm`] and the frame's geometry pixels N. Per region with P
/// penumbra pixels, a narrowest penumbra W pixels wide (width over footprint) and n samples per
/// side:
/// - its shadow edges are L = P / max(1, W) pixels long;
/// - its texel spans τ = max(1, W/n)/D footprints (the texel need of `classify`);
/// - each map moves an edge by up to half a texel; the squared error over the band is τ/12 per
///   pixel of edge for one map;
/// - the n columns of samples put n edges W/n footprints apart. Where that gap is at least a
///   texel (W/n ≥ τ, so D ≥ n/W below W = n, always above) each column's edge errs alone, with
///   a weight of 1/n: the error falls to a = (1 + 3/n)/n of one map's (at most 1). Closer, the
///   edges' errors overlap and add as one map's (a = 1).
///
/// `params` carries the samples' target: n is the count `classify` gave the region.
pub fn edge_terms(params: &RegionsParams, regions: &[u32]) -> (Vec<EdgeTerm>, f64) {
    let totals = total(params, regions);
    let mut terms = Vec::new();
    for r in regions.chunks(REGION_WORDS).take(params.region_count as usize) {
        let (area, penumbra) = (r[0], r[1]);
        if penumbra == 0 || r[2] == u32::MAX || r[3] == u32::MAX {
            continue;
        }
        let (foot, width) = (unordered(r[2]) as f64, unordered(r[3]) as f64);
        let w = if foot > 0.0 { width / foot } else { 0.0 };
        let n = samples_of(params, totals, area, penumbra) as f64;
        let together = penumbra as f64 / w.max(1.0) * (w / n).max(1.0);
        let apart_from = if w >= n { 0.0 } else if w > 0.0 { n / w } else { f64::INFINITY };
        terms.push(EdgeTerm { apart_from, together, apart: together * ((1.0 + 3.0 / n) / n).min(1.0) });
    }
    (terms, totals[1].max(1) as f64)
}

/// The frame's edge weight E at `density` texels per footprint.
pub fn edge_weight(terms: &[EdgeTerm], density: f64) -> f64 {
    terms.iter().map(|t| t.at(density)).sum()
}

/// The maps' RMSE over the frame's geometry pixels at `density` texels per footprint.
pub fn predicted_map(e: f64, pixels: f64, density: f64) -> f64 {
    (e / (12.0 * density * pixels)).sqrt()
}

/// The least density D, never below `floor` (the lookup's offsets, `State::density_floor`), whose
/// predicted maps' error E(D)/(12 D N) is at most the maps' share of `target` (T_m² = T² − T_s²).
/// E(D) only falls as D grows (more columns' edges lie a texel apart), so D − E(D)/(12 N T_m²)
/// rises: the first interval between the terms' thresholds where it reaches 0 holds the answer.
pub fn map_density(terms: &[EdgeTerm], pixels: f64, target: f64, floor: f64) -> f64 {
    let share = target * target * (1.0 - (SAMPLING_SHARE as f64).powi(2));
    let per = 12.0 * pixels * share;
    let mut steps: Vec<f64> = terms.iter().map(|t| t.apart_from).filter(|&d| d > floor && d.is_finite()).collect();
    steps.sort_by(f64::total_cmp);
    steps.dedup();
    let mut from = floor;
    for next in steps.into_iter().chain([f64::INFINITY]) {
        let d = from.max(edge_weight(terms, from) / per);
        if d < next {
            return d;
        }
        from = next;
    }
    unreachable!("the last interval is unbounded")
}
