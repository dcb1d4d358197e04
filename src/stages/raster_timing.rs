//! Wall-clock timing of the shadow-map raster on a scene: a few maps of the scene's light, drawn in
//! rounds after a warm-up, the least time of each raster kept. `raster = auto` compares the two
//! rasters with it.

use super::raster::{Raster, RasterTarget};
use crate::gpu::readback;
use crate::gpu::GpuContext;
use crate::render::shadow_raster::RasterJob;
use crate::render::SceneGpu;
use crate::scene::light::sample_view;
use crate::scene::Scene;
use crate::Result;
use std::hash::{Hash, Hasher};
use std::time::Instant;

/// The least wall-clock time (ms) each of `rasters` takes to draw `maps` maps of side `size`, over
/// `rounds` rounds after one warm-up round that is not counted. The rasters take turns, so a
/// device that warms up or throttles over the rounds weighs on each alike.
pub fn least_ms(
    ctx: &GpuContext,
    scene: &Scene,
    gpu: &SceneGpu,
    rasters: &[&Raster],
    size: u32,
    maps: u32,
    rounds: usize,
) -> Result<Vec<f64>> {
    // Light points spread over the light, as a grid's would be.
    let samples: Vec<_> = (0..maps)
        .map(|k| {
            let (u, v) = ((k % 3) as f32 * 0.5, (k / 3 % 3) as f32 * 0.5);
            sample_view(
                &scene.light,
                scene.light.point(u, v),
                &scene.bounds,
                size,
                k,
            )
        })
        .collect();
    let buffer = readback::storage_buffer(
        ctx,
        "raster timing samples",
        &samples,
        wgpu::BufferUsages::empty(),
    );
    let jobs: Vec<RasterJob> = (0..maps)
        .map(|k| RasterJob {
            sample: k,
            layer: k,
            scissor: None,
        })
        .collect();
    let arrays: Vec<_> = rasters
        .iter()
        .map(|r| r.allocate(ctx, size, maps))
        .collect();
    let mut best = vec![f64::INFINITY; rasters.len()];
    for round in 0..=rounds {
        for (i, r) in rasters.iter().enumerate() {
            let start = Instant::now();
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            r.record(
                ctx,
                &mut enc,
                &RasterTarget {
                    scene: gpu,
                    samples: &buffer,
                    array: &arrays[i],
                },
                &jobs,
            )?;
            ctx.queue.submit([enc.finish()]);
            ctx.wait()?;
            if round > 0 {
                best[i] = best[i].min(start.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    Ok(best)
}

/// A hash of the scene's mesh, for remembering a timing per (adapter, mesh, …) in a process.
pub(crate) fn mesh_hash(scene: &Scene) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    bytemuck::cast_slice::<_, u8>(&scene.vertices).hash(&mut h);
    scene.indices.hash(&mut h);
    h.finish()
}
