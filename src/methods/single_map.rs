//! What the single-map methods (pcf, pcss and the filtered maps) share: one shadow map from the
//! light's centre, the filter uniform, and the capture their twin tests read.

use crate::compute::FrameGpu;
use crate::gpu::readback;
use crate::layout::{GpuFilter, GpuSample};
use crate::light::sample_view;
use crate::render::shadow_raster::{self, RasterJob, ShadowMapArray};
use crate::timing::StageTimer;
use crate::Result;

/// The map from the light's centre, allocated once per scene and settings.
pub struct CentreMap {
    pub sample: GpuSample,
    pub samples: wgpu::Buffer,
    pub array: ShadowMapArray,
}

impl CentreMap {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        let s = fg.scene;
        let mut sample = sample_view(&s.light, s.light.point(0.5, 0.5), &s.bounds, s.render.shadow_map_size, u32::MAX);
        sample.layer = 0;
        let samples = readback::storage_buffer(fg.ctx, "centre sample", &[sample], wgpu::BufferUsages::empty());
        let array = shadow_raster::allocate(fg.ctx, s.render.shadow_map_size, 1);
        shadow_raster::clear_all(fg.ctx, &array)?;
        Ok(Self { sample, samples, array })
    }

    /// The `shadow_raster` stage: one map.
    pub fn render(&self, fg: &FrameGpu, timer: &mut StageTimer) -> Result<()> {
        timer.stage(fg.ctx, "shadow_raster", |enc| {
            fg.raster.record(fg.ctx, enc, &fg.scene_gpu, &self.samples, &self.array, &[RasterJob { sample: 0, layer: 0, scissor: None }]);
            Ok(())
        })
    }

    pub fn read(&self, fg: &FrameGpu) -> Result<Vec<f32>> {
        readback::read_texture(fg.ctx, &self.array.texture, 0, 4)
    }

    /// The map's far plane: linear depth a / (1 + b) of the cleared depth 1.
    pub fn far_depth(&self) -> f32 {
        self.sample.depth_lin_a / (1.0 + self.sample.depth_lin_b)
    }
}

/// The area light's edge lengths: the light size every single-map method takes from the scene.
pub fn light_size(fg: &FrameGpu) -> (f32, f32) {
    (fg.scene.light.edge_u.length(), fg.scene.light.edge_v.length())
}

/// Inputs and intermediate buffers of one single-map frame, kept for the twins (`capture`).
#[derive(Clone, Debug, Default)]
pub struct SingleMapCapture {
    pub map: Vec<f32>,
    pub sample: GpuSample,
    pub filter: GpuFilter,
    /// pcf: tap offsets of the disk kernels.
    pub disk: Vec<[f32; 2]>,
    /// Filtered methods: the statistic as `moments` wrote it, after the horizontal blur, after both.
    pub raw: Vec<[f32; 4]>,
    pub scratch: Vec<[f32; 4]>,
    pub filtered: Vec<[f32; 4]>,
}

/// The capture of a single-map run made with `capture` on.
pub fn capture_of(out: &crate::methods::MethodOutput) -> Option<&SingleMapCapture> {
    out.detail.as_ref()?.downcast_ref()
}
