//! The price of one map of each size for `auto`'s search under `cost = measured`
//! (docs/error-estimate.md §6): what a map of that size adds to a settled frame of this scene on
//! this device. A map's frame is more than its raster: the grid's chunks and clears, and shade,
//! which costs the same per map at every size (a raster-only price favours large maps where the
//! raster is cheap against it). So each size is priced from the stages of frames of the centred
//! 2×2 grid, the passes a settled `auto` frame runs, read as a frame reads them (a median).
//! Measured before the clock, once per process and scene.

use crate::gpu::timing::{StageTimer, TimingMode};
use crate::methods::fixed_samples::{self, regular_points, Layout};
use crate::methods::MethodState;
use crate::stages::FrameGpu;
use crate::Result;
use std::time::Instant;

/// The grid whose frames price a size: four maps, as the raster's own timing draws.
const SIDE: u32 = 2;
/// Timed rounds after one warm-up round that is not counted; each size's figure is the median.
const ROUNDS: usize = 3;

/// The price of one map from a frame's timed stages: everything the grid's `maps` added to the
/// frame (its raster, clears and culling, shade's lookups), per map. The G-buffer, the clear of
/// V and the read-back are the frame's whatever its maps, and are not in `stages_ms`.
pub(crate) fn per_map(stages_ms: &std::collections::BTreeMap<String, f64>, maps: usize) -> f64 {
    stages_ms.values().sum::<f64>() / maps.max(1) as f64
}

/// The price of one map at each of `sizes` (ascending), in that order, a larger map never priced
/// below a smaller one (a timing that says so is the clock's noise, and would send the search to
/// it), and the wall time the pricing took (0 where this process had priced the same scene).
/// The caller (`auto`) names the sizes, so this module needs nothing of its search.
pub(crate) fn measured(fg: &FrameGpu, sizes: &[u32]) -> Result<(Vec<(u32, f64)>, f64)> {
    let key = key(fg, sizes);
    if let Some(costs) = remembered().lock().ok().and_then(|m| m.get(&key).cloned()) {
        return Ok((costs, 0.0));
    }
    let start = Instant::now();
    // The grids of every size are held at once, so the rounds take turns over all of them and a
    // device that warms up or slows over the rounds weighs on each alike.
    let mut grids = Vec::new();
    for &z in sizes {
        let frame = crate::gpu::readback::uniform_buffer(
            fg.ctx,
            "auto price frame",
            &crate::gpu::structs::GpuFrame {
                map_size: z,
                ..fg.frame
            },
        );
        grids.push(fixed_samples::prepare_sized(
            fg,
            &regular_points(SIDE, Layout::Centred),
            z,
            Some(frame),
        )?);
    }
    let mut times = vec![Vec::new(); grids.len()];
    for round in 0..=ROUNDS {
        for (grid, t) in grids.iter_mut().zip(&mut times) {
            // Stage by stage, as a settled frame's `stages_ms`: a wait after each stage.
            let mut timer = StageTimer::new(TimingMode::Stages);
            fg.clear_visibility();
            grid.reset(fg)?;
            grid.run(fg, &mut timer, false)?;
            timer.flush(fg.ctx);
            fg.ctx.wait()?;
            if round > 0 {
                t.push(per_map(&timer.stages_ms, grid.map_count()));
            }
        }
    }
    let mut priced: Vec<(u32, f64)> = Vec::new();
    for (&z, t) in sizes.iter().zip(&times) {
        let floor = priced.last().map_or(0.0, |&(_, c)| c);
        priced.push((z, median(t).max(floor)));
    }
    if let Ok(mut m) = remembered().lock() {
        m.insert(key, priced.clone());
    }
    Ok((priced, start.elapsed().as_secs_f64() * 1e3))
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s[s.len() / 2]
}

/// What a price depends on: the adapter, the scene's mesh and light, the raster, cull and budget,
/// the screen (shade's share) and the sizes.
fn key(fg: &FrameGpu, sizes: &[u32]) -> String {
    let s = fg.scene;
    format!(
        "{}|{}|{:?}|{}|{}|{:?} {:?}|{}x{}|{:?}",
        fg.ctx.summary.name,
        crate::stages::raster_timing::mesh_hash(s),
        s.render.cull,
        fg.raster.name(),
        s.render.shadow_map_budget_mib,
        s.emitter.kind(),
        s.light,
        fg.gbuffer.width,
        fg.gbuffer.height,
        sizes
    )
}

type Prices = std::sync::Mutex<std::collections::HashMap<String, Vec<(u32, f64)>>>;

fn remembered() -> &'static Prices {
    static PRICES: std::sync::OnceLock<Prices> = std::sync::OnceLock::new();
    PRICES.get_or_init(Default::default)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_map_is_priced_at_what_its_stages_add_to_the_frame() {
        // Four maps whose raster took 36 ms and shade 4 ms: 10 ms a map.
        let stages: std::collections::BTreeMap<String, f64> = [
            ("shadow_raster".to_string(), 36.0),
            ("shade".to_string(), 4.0),
        ]
        .into();
        assert_eq!(per_map(&stages, 4), 10.0);
        // A point light's 2×2 grid: 24 maps.
        assert_eq!(per_map(&stages, 24), 40.0 / 24.0);
        assert_eq!(median(&[5.0, 1.0, 3.0]), 3.0);
    }
}
