//! Methods with a fixed sample set (hard, regular): raster every map, shade, chunk by chunk when the
//! maps exceed the memory budget or the layer limit.

use super::{check_range, params, Family, MethodInfo, MethodOutput, MethodState, Param, ParamMap, ShadowMethod};
use crate::compute::FrameGpu;
use crate::gpu::readback;
use crate::layout::GpuSample;
use crate::light::sample_view;
use crate::render::shadow_raster::{self, RasterJob};
use crate::timing::StageTimer;
use crate::Result;

pub const HARD: MethodInfo = MethodInfo {
    name: "hard",
    family: Family::Hard,
    summary: "one shadow map from the light's centre, one binary test per pixel",
    params: &[],
    parse: |_| Ok(std::sync::Arc::new(Fixed::Hard)),
};

pub const REGULAR: MethodInfo = MethodInfo {
    name: "regular",
    family: Family::MultiSample,
    summary: "N×N shadow maps on the light's lattice corners, equal weights",
    params: &[Param { key: "n", default: "17", help: "samples per side, 1..=128 (17 gives the 289 lattice points)" }],
    parse: |p: &ParamMap| {
        let n = check_range("regular", "n", params::get_u32(p, "n", 17)?, 1, 128)?;
        Ok(std::sync::Arc::new(Fixed::Regular { n }))
    },
};

/// Hard (one map from the centre) or the regular N×N grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fixed {
    Hard,
    Regular { n: u32 },
}

impl Fixed {
    pub fn points(&self) -> Vec<(f32, f32)> {
        match self {
            Fixed::Hard => vec![(0.5, 0.5)],
            Fixed::Regular { n } => regular_points(*n),
        }
    }
}

impl ShadowMethod for Fixed {
    fn name(&self) -> &'static str {
        match self {
            Fixed::Hard => "hard",
            Fixed::Regular { .. } => "regular",
        }
    }
    fn label(&self) -> String {
        match self {
            Fixed::Hard => "hard".into(),
            Fixed::Regular { n } => format!("regular:n={n}"),
        }
    }
    fn params_json(&self) -> serde_json::Value {
        match self {
            Fixed::Hard => serde_json::json!({}),
            Fixed::Regular { n } => serde_json::json!({ "n": n }),
        }
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        Ok(Box::new(prepare(fg, &self.points())?))
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

impl MethodState for Prepared {
    fn reset(&mut self, _fg: &FrameGpu) -> Result<()> {
        Ok(()) // every raster pass clears its layer
    }
    fn run(&mut self, fg: &FrameGpu, timer: &mut StageTimer, capture: bool) -> Result<MethodOutput> {
        run(fg, timer, self, capture)
    }
}

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
fn run(fg: &FrameGpu, timer: &mut StageTimer, prepared: &Prepared, capture: bool) -> Result<MethodOutput> {
    let ctx = fg.ctx;
    let Prepared { points, chunk, samples, weights, samples_buffer, weights_buffer, array } = prepared;
    let (points, chunk) = (*points, *chunk);
    let mut capture = capture.then(FixedCapture::default);
    let inputs = fg.shade_inputs(&samples_buffer, &weights_buffer);
    let bar = crate::progress::bar(points as u64, "shadow maps");
    for first in (0..points as u32).step_by(chunk as usize) {
        let count = chunk.min(points as u32 - first);
        let jobs: Vec<RasterJob> = (first..first + count).map(|i| RasterJob { sample: i, layer: i - first, scissor: None }).collect();
        timer.stage(ctx, "shadow_raster", |enc| {
            fg.raster.record(ctx, enc, &fg.scene_gpu, samples_buffer, array, &jobs);
            Ok(())
        })?;
        if let Some(c) = capture.as_mut() {
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
    if let Some(c) = capture.as_mut() {
        c.samples = samples.clone();
        c.weights = weights.clone();
    }
    let chunks = (points as u32).div_ceil(chunk);
    Ok(MethodOutput {
        shadow_maps: points as u32,
        syncs: 0,
        record: serde_json::json!({ "maps_per_chunk": chunk, "chunks": chunks }),
        pictures: Vec::new(),
        detail: capture.map(|c| Box::new(c) as Box<dyn std::any::Any>),
    })
}

/// The capture of a fixed-sample run made with `capture` on.
pub fn capture_of(out: &MethodOutput) -> Option<&FixedCapture> {
    out.detail.as_ref()?.downcast_ref()
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
