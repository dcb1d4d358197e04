//! `raster = auto`: whichever raster this adapter runs faster on the scene. Both rasterize the same
//! few maps of the scene's light, alternately, after a warm-up; the least wall-clock time of each
//! decides. A process measures each (adapter, mesh, map size, cull) once and remembers it, so every
//! method of a comparison or a sweep rasterizes the same way.

use super::raster::Raster;
use crate::gpu::GpuContext;
use crate::render::SceneGpu;
use crate::scene::{MapKind, RasterChoice, Scene};
use crate::Result;
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

/// Maps each raster draws per round: enough to amortise a submission, few enough to stay quick.
pub(crate) const AUTO_MAPS: u32 = 8;
/// Timed rounds per raster, alternating.
pub(crate) const AUTO_ROUNDS: usize = 3;

/// What `auto` measured (wall clock, one round of AUTO_MAPS maps each, the least of AUTO_ROUNDS).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub(crate) struct AutoTiming {
    pub(crate) hardware_ms: f64,
    pub(crate) compute_ms: f64,
    pub(crate) maps: u32,
    pub(crate) map_size: u32,
    pub(crate) compute: bool,
}

type Key = (String, u64, u32, String, u32);

fn remembered() -> &'static Mutex<HashMap<Key, AutoTiming>> {
    static CHOICES: OnceLock<Mutex<HashMap<Key, AutoTiming>>> = OnceLock::new();
    CHOICES.get_or_init(|| Mutex::new(HashMap::new()))
}

/// The size the raster draws at: `hybrid.base` under maps = hybrid.
pub(crate) fn raster_size(scene: &Scene) -> u32 {
    match scene.render.maps {
        MapKind::Hybrid => scene.render.hybrid.base,
        MapKind::Plain => scene.render.shadow_map_size,
    }
}

fn key(ctx: &GpuContext, scene: &Scene) -> Key {
    (
        ctx.summary.name.clone(),
        super::raster_timing::mesh_hash(scene),
        raster_size(scene),
        format!("{:?}", scene.render.cull),
        scene.render.shadow_map_budget_mib,
    )
}

/// Whether the frame rasterizes in compute kernels, by the scene's `raster` setting, and what
/// `auto` measured when it chose.
pub(crate) fn compute_raster(
    ctx: &GpuContext,
    scene: &Scene,
    gpu: &SceneGpu,
) -> Result<(bool, Option<AutoTiming>)> {
    Ok(match scene.render.raster {
        RasterChoice::Hardware => (false, None),
        RasterChoice::Compute => (true, None),
        RasterChoice::Auto => {
            let t = timing(ctx, scene, gpu)?;
            (t.compute, Some(t))
        }
    })
}

fn timing(ctx: &GpuContext, scene: &Scene, gpu: &SceneGpu) -> Result<AutoTiming> {
    let k = key(ctx, scene);
    if let Some(t) = remembered().lock().ok().and_then(|m| m.get(&k).copied()) {
        return Ok(t);
    }
    let size = raster_size(scene);
    let budget = scene.render.shadow_map_budget_mib;
    let rasters = [
        Raster::new(ctx, scene.render.cull, false, budget)?,
        Raster::new(ctx, scene.render.cull, true, budget)?,
    ];
    let maps = rasters
        .iter()
        .map(|r| r.maps_per_array(ctx, size, budget))
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .min()
        .unwrap_or(1)
        .min(AUTO_MAPS);
    let best = super::raster_timing::least_ms(
        ctx,
        scene,
        gpu,
        &[&rasters[0], &rasters[1]],
        size,
        maps,
        AUTO_ROUNDS,
    )?;
    let t = AutoTiming {
        hardware_ms: best[0],
        compute_ms: best[1],
        maps,
        map_size: size,
        compute: best[1] < best[0],
    };
    if let Ok(mut m) = remembered().lock() {
        m.insert(k, t);
    }
    Ok(t)
}
