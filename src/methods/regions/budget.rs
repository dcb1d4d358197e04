//! `regions`' error budget (docs/regions.md, "The target's two parts"): the frame's squared
//! target splits evenly between the light samples and the maps' texels. The samples' half is the
//! `classify` kernel's target; the maps' half sets the texel density, from a model of the maps'
//! error that reads only what `measure` kept per region.

use crate::stages::regions::{unordered, RegionsParams, REGION_WORDS};
use crate::stages::regions_rules::{samples_of, total};

/// The samples' share of the target: T_s = T/√2, so T_s² + T_m² = T² with T_m = T_s.
pub const SAMPLING_SHARE: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// The frame's edge weight E and geometry pixels N, so that at D texels per pixel footprint the
/// maps' error is m² = E / (12 D N) (docs/regions.md). Per region with P penumbra pixels, a
/// narrowest penumbra W pixels wide (width over footprint) and n samples per side:
/// - its shadow edges are L = P / max(1, W) pixels long;
/// - its texel spans max(1, W/n)/D footprints (the texel need of `classify`);
/// - each map moves an edge by up to half a texel; the squared error over the band is τ/12 per
///   pixel of edge for one map (τ: the texel in footprints), and falls to (1 + 3/n)/n of that
///   where the n columns of samples' edges lie apart (W ≥ n), their maps' errors independent.
///
/// `params` carries the samples' target: n is the count `classify` gave the region.
pub fn edge_weight(params: &RegionsParams, regions: &[u32]) -> (f64, f64) {
    let totals = total(params, regions);
    let mut e = 0.0f64;
    for r in regions
        .chunks(REGION_WORDS)
        .take(params.region_count as usize)
    {
        let (area, penumbra) = (r[0], r[1]);
        if penumbra == 0 || r[2] == u32::MAX || r[3] == u32::MAX {
            continue;
        }
        let (foot, width) = (unordered(r[2]) as f64, unordered(r[3]) as f64);
        let w = if foot > 0.0 { width / foot } else { 0.0 };
        let n = samples_of(params, totals, area, penumbra) as f64;
        let length = penumbra as f64 / w.max(1.0);
        let texel = (w / n).max(1.0);
        let apart = if w >= n {
            ((1.0 + 3.0 / n) / n).min(1.0)
        } else {
            1.0
        };
        e += length * texel * apart;
    }
    (e, totals[1].max(1) as f64)
}

/// The maps' RMSE over the frame's geometry pixels at `density` texels per footprint.
pub fn predicted_map(e: f64, pixels: f64, density: f64) -> f64 {
    (e / (12.0 * density * pixels)).sqrt()
}

/// The least density whose predicted maps' error is at most the maps' share of `target`
/// (T_m² = T² − T_s²), and never below `floor` (the lookup's offsets, `State::density`).
pub fn map_density(e: f64, pixels: f64, target: f64, floor: f64) -> f64 {
    let share = target * target * (1.0 - (SAMPLING_SHARE as f64).powi(2));
    (e / (12.0 * pixels * share)).max(floor)
}
