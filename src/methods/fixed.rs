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

/// Buffers and the map array of a fixed-sample run, allocated before the frame's clock starts.
pub struct Prepared {
    points: usize,
    chunk: u32,
    samples: Vec<GpuSample>,
    weights: Vec<f32>,
    samples_buffer: wgpu::Buffer,
    weights_buffer: wgpu::Buffer,
    array: shadow_raster::ShadowMapArray,
}

/// Samples (s, t) with equal weights; the array holds at most `maps_per_array` maps.
pub fn prepare(fg: &FrameGpu, points: &[(f32, f32)]) -> Result<Prepared> {
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
    shadow_raster::clear_all(ctx, &array)?;
    Ok(Prepared { points: points.len(), chunk, samples, weights, samples_buffer, weights_buffer, array })
}

/// Renders and shades chunk by chunk; with `capture`, every map and sample record is kept for the
/// shade twin (tests only).
pub fn run(fg: &FrameGpu, timer: &mut StageTimer, prepared: Prepared, mut capture: Option<&mut FixedCapture>) -> Result<MethodOutput> {
    let ctx = fg.ctx;
    let Prepared { points, chunk, samples, weights, samples_buffer, weights_buffer, array } = prepared;
    let inputs = fg.shade_inputs(&samples_buffer, &weights_buffer);
    let bar = crate::progress::bar(points as u64, "shadow maps");
    for first in (0..points as u32).step_by(chunk as usize) {
        let count = chunk.min(points as u32 - first);
        let jobs: Vec<RasterJob> = (first..first + count).map(|i| RasterJob { sample: i, layer: i - first, scissor: None }).collect();
        timer.stage(ctx, "shadow_raster", |enc| {
            fg.raster.record(ctx, enc, &fg.scene_gpu, &samples_buffer, &array, &jobs);
            Ok(())
        })?;
        if let Some(c) = capture.as_deref_mut() {
            timer.flush(ctx);
            for layer in 0..count {
                c.maps.push(readback::read_texture(ctx, &array.texture, layer, 4)?);
            }
        }
        timer.stage(ctx, "shade", |enc| {
            fg.shade.record(ctx, enc, &inputs, &array.array_view, first, count);
            Ok(())
        })?;
        bar.inc(count as u64);
    }
    bar.finish_and_clear();
    if let Some(c) = capture {
        c.samples = samples;
        c.weights = weights;
    }
    let chunks = (points as u32).div_ceil(chunk);
    Ok(MethodOutput {
        shadow_maps: points as u32,
        syncs: 0,
        record: serde_json::json!({ "maps_per_chunk": chunk, "chunks": chunks }),
        pictures: Vec::new(),
    })
}

/// Maps, samples and weights of a fixed-sample run, for the shade twin.
#[derive(Default)]
pub struct FixedCapture {
    pub maps: Vec<Vec<f32>>,
    pub samples: Vec<GpuSample>,
    pub weights: Vec<f32>,
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
