//! Methods with a fixed sample set (hard, regular): raster every map, shade, chunk by chunk when the
//! maps exceed the memory budget or the layer limit.

use crate::frame::{FrameGpu, MethodOutput};
use crate::gpu::readback;
use crate::layout::GpuSample;
use crate::light::sample_view;
use crate::render::shadow_raster::{self, RasterJob};
use crate::timing::StageTimer;
use crate::Result;

/// Light points (s, t) of the regular N×N grid in `layout` (docs/method.md §7):
/// - lattice: the corners i/(N-1), edges included, so N = 17 gives exactly the 289 points of §3
///   (N = 1 is the centre); the mean over a closed lattice weights the light's boundary too much;
/// - centred: the cell centres (i+½)/N, the midpoint rule;
/// - jittered: one point per cell at (i+u)/N, u uniform from a fixed seed (stratified sampling).
pub fn regular_points(n: u32, layout: Layout) -> Vec<(f32, f32)> {
    let cells = move |offset: &dyn Fn(u32, u32) -> (f32, f32)| -> Vec<(f32, f32)> {
        (0..n)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .map(|(i, j)| {
                let (u, v) = offset(i, j);
                ((i as f32 + u) / n as f32, (j as f32 + v) / n as f32)
            })
            .collect()
    };
    match layout {
        Layout::Lattice if n == 1 => vec![(0.5, 0.5)],
        Layout::Lattice => {
            let step = 1.0 / (n - 1) as f32;
            (0..n).flat_map(|j| (0..n).map(move |i| (i as f32 * step, j as f32 * step))).collect()
        }
        Layout::Centred => cells(&|_, _| (0.5, 0.5)),
        Layout::Jittered => cells(&|i, j| {
            let h = splitmix64(JITTER_SEED ^ ((j as u64) << 32 | i as u64));
            ((h >> 40) as f32 / (1u64 << 24) as f32, ((h >> 16) & 0xff_ffff) as f32 / (1u64 << 24) as f32)
        }),
    }
}

/// Where the N×N grid's points sit in their cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Layout {
    Lattice,
    Centred,
    Jittered,
}

/// The fixed seed of `layout = jittered`, so runs repeat exactly.
const JITTER_SEED: u64 = 0x5eed_0f_9e11;

fn splitmix64(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
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
    use super::{regular_points, Layout};

    #[test]
    fn centred_and_jittered_are_stratified() {
        for layout in [Layout::Centred, Layout::Jittered] {
            let p = regular_points(9, layout);
            assert_eq!(p.len(), 81);
            for (k, (s, t)) in p.iter().enumerate() {
                let (i, j) = ((k % 9) as f32, (k / 9) as f32);
                assert!(*s > i / 9.0 && *s < (i + 1.0) / 9.0 && *t > j / 9.0 && *t < (j + 1.0) / 9.0, "{layout:?} point {k} ({s}, {t}) outside its cell");
            }
        }
        assert_eq!(regular_points(2, Layout::Centred), vec![(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)]);
        let jitter = regular_points(9, Layout::Jittered);
        assert_eq!(jitter, regular_points(9, Layout::Jittered), "jittered is seeded, so runs repeat");
        assert!(jitter.iter().zip(regular_points(9, Layout::Centred)).filter(|(a, b)| **a != *b).count() == 81);
    }

    #[test]
    fn regular_17_is_the_lattice() {
        let p = regular_points(17, Layout::Lattice);
        assert_eq!(p.len(), 289);
        for (k, (s, t)) in p.iter().enumerate() {
            assert_eq!(*s, (k % 17) as f32 / 16.0);
            assert_eq!(*t, (k / 17) as f32 / 16.0);
        }
    }
}
