//! The GPU state of one scene that every method works on: uploaded geometry, the camera G-buffer,
//! the frame uniform, the shared raster and shade passes and the visibility buffer. It lives below
//! the methods and the passes, so data flows one way: frame driver ─► methods ─► passes. Only what
//! every frame shares belongs here (per-run options such as pictures are `run` arguments), and the
//! passes take the parts they read, not the whole, so a test can drive one without building it.

use super::raster::Raster;
use super::shade::{GeometryTiles, Screen, ShadeInputs, ShadePass};
use crate::gpu::kernels::MapAccess;
use crate::gpu::structs::GpuFrame;
use crate::gpu::GpuContext;
use crate::render::gbuffer::GBuffer;
use crate::render::SceneGpu;
use crate::scene::Scene;

/// What a method builds and runs on: the context and the scene the renderer holds, and the frame's
/// shared GPU parts, read through `Deref` (`fg.gbuffer`). A view the renderer lends for one call,
/// so the renderer can own its context and scene (`frame::Held`) without borrowing itself.
#[derive(Clone, Copy)]
pub struct FrameGpu<'a> {
    pub(crate) ctx: &'a GpuContext,
    pub(crate) scene: &'a Scene,
    pub(crate) parts: &'a FrameParts,
}

impl std::ops::Deref for FrameGpu<'_> {
    type Target = FrameParts;
    fn deref(&self) -> &FrameParts {
        self.parts
    }
}

/// The frame's own GPU objects, which the renderer owns and every method shares.
pub struct FrameParts {
    pub(crate) scene_gpu: SceneGpu,
    pub(crate) gbuffer: GBuffer,
    pub(crate) frame: GpuFrame,
    pub(crate) frame_buffer: wgpu::Buffer,
    /// The shadow-map raster the `raster` setting chose; methods allocate their arrays from it.
    pub(crate) raster: Raster,
    pub(crate) shade: ShadePass,
    /// This frame's 8x8 tiles with a geometry pixel, listed with the G-buffer.
    pub(crate) geometry_tiles: GeometryTiles,
    pub(crate) visibility: wgpu::Buffer,
    /// Shadow maps kept from the renderer's earlier frames, for the method's state to take
    /// (docs/reuse.md); empty with reuse off.
    pub(crate) maps_kept: crate::render::kept_maps::MapCache,
}

impl FrameGpu<'_> {
    pub(crate) fn shade_inputs<'b>(
        &'b self,
        samples: &'b wgpu::Buffer,
        weights: &'b wgpu::Buffer,
    ) -> ShadeInputs<'b> {
        ShadeInputs {
            frame: &self.frame_buffer,
            samples,
            weights,
            gbuffer: &self.gbuffer,
            tiles: &self.geometry_tiles,
            visibility: &self.visibility,
        }
    }
    /// The frame's screen: what every per-pixel pass covers, and V.
    pub(crate) fn screen(&self) -> Screen<'_> {
        Screen {
            frame: &self.frame_buffer,
            gbuffer: &self.gbuffer,
            tiles: &self.geometry_tiles,
            visibility: &self.visibility,
        }
    }
    /// How this frame's map-reading kernels read the scene's maps.
    pub(crate) fn map_access(&self) -> MapAccess {
        self.raster.access(self.scene.render.maps)
    }
    /// V cleared in a submission of its own, ahead of what is recorded after it (a method that
    /// renders V more than once a frame: auto's tries and one-map checks).
    pub(crate) fn clear_visibility(&self) {
        let mut enc = self.ctx.device.create_command_encoder(&Default::default());
        enc.clear_buffer(&self.visibility, 0, None);
        self.ctx.queue.submit([enc.finish()]);
    }
    pub(crate) fn pixel_count(&self) -> u32 {
        self.gbuffer.width * self.gbuffer.height
    }
}
