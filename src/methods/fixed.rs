//! Methods with a fixed sample set (hard, regular): raster every map, shade, chunk by chunk when the
//! maps exceed the memory budget or the layer limit.

use crate::frame::{FrameGpu, MethodOutput};
use crate::gpu::readback;
use crate::layout::GpuSample;
use crate::light::sample_view;
use crate::render::shadow_raster::{self, RasterJob};
use crate::timing::StageTimer;
use crate::Result;

/// Light points (s, t) of the regular N×N grid: the lattice corners i/(N-1), edges included,
/// so N = 17 gives exactly the 289 points of method.md §3. N = 1 is the centre.
pub fn regular_points(n: u32) -> Vec<(f32, f32)> {
    if n == 1 {
        return vec![(0.5, 0.5)];
    }
    let step = 1.0 / (n - 1) as f32;
    (0..n).flat_map(|j| (0..n).map(move |i| (i as f32 * step, j as f32 * step))).collect()
}

/// Samples (s, t) with equal weights, rendered and shaded in chunks of at most `maps_per_array`.
pub fn run(fg: &FrameGpu, timer: &mut StageTimer, points: &[(f32, f32)]) -> Result<MethodOutput> {
    let ctx = fg.ctx;
    let s = &fg.scene;
    let per_array = shadow_raster::maps_per_array(ctx, s.render.shadow_map_size, s.render.shadow_map_budget_mib)?;
    let chunk = per_array.min(points.len() as u32).max(1);
    let samples: Vec<GpuSample> = points
        .iter()
        .enumerate()
        .map(|(i, &(u, v))| {
            let mut g = sample_view(&s.light, s.light.point(u, v), &s.bounds, s.render.shadow_map_size, u32::MAX);
            g.layer = i as u32 % chunk;
            g
        })
        .collect();
    let weights = vec![1.0 / points.len() as f32; points.len()];
    let samples_buffer = readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty());
    let weights_buffer = readback::storage_buffer(ctx, "weights", &weights, wgpu::BufferUsages::empty());
    let array = shadow_raster::allocate(ctx, s.render.shadow_map_size, chunk);
    let inputs = fg.shade_inputs(&samples_buffer, &weights_buffer);
    let bar = crate::progress::bar(points.len() as u64, "shadow maps");
    for first in (0..points.len() as u32).step_by(chunk as usize) {
        let count = chunk.min(points.len() as u32 - first);
        let jobs: Vec<RasterJob> = (first..first + count).map(|i| RasterJob { sample: i, layer: i - first, scissor: None }).collect();
        timer.stage(ctx, "shadow_raster", |enc| {
            fg.raster.record(ctx, enc, &fg.scene_gpu, &samples_buffer, &array, &jobs);
            Ok(())
        })?;
        timer.stage(ctx, "shade", |enc| {
            fg.shade.record(ctx, enc, &inputs, &array.array_view, first, count);
            Ok(())
        })?;
        bar.inc(count as u64);
    }
    bar.finish_and_clear();
    let chunks = (points.len() as u32).div_ceil(chunk);
    Ok(MethodOutput {
        shadow_maps: points.len() as u32,
        syncs: 0,
        record: serde_json::json!({ "maps_per_chunk": chunk, "chunks": chunks }),
        pictures: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn regular_17_is_the_lattice() {
        let p = super::regular_points(17);
        assert_eq!(p.len(), 289);
        for (k, (s, t)) in p.iter().enumerate() {
            assert_eq!(*s, (k % 17) as f32 / 16.0);
            assert_eq!(*t, (k / 17) as f32 / 16.0);
        }
    }
}
