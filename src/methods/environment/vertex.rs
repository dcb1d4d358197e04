//! env-pixels:at=vertex, the seed's per-vertex variant: env_trace's `vertex` entry point sums the
//! pixel lights at every mesh vertex, the barycentrics raster finds each pixel's triangle and
//! barycentrics, and env_vertex_interp interpolates the three vertex values (docs/environment.md §2).

use crate::gpu::readback;
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::render::barycentrics::{self, BarycentricsPass, TriangleIds};
use crate::stages::env_trace::{BvhBuffers, EnvTraceVertex, VertexMesh, VertexOutputs};
use crate::stages::env_vertex_interp::{EnvVertexInterp, InterpInputs};
use crate::stages::FrameGpu;
use crate::Result;

pub(crate) struct VertexStage {
    raster: BarycentricsPass,
    ids: TriangleIds,
    camera: wgpu::Buffer,
    trace: EnvTraceVertex,
    interp: EnvVertexInterp,
    pub(crate) vertex_count: u32,
    visibility: wgpu::Buffer,
    blocked: wgpu::Buffer,
    sums: wgpu::Buffer,
}

/// What the twins need of a per-vertex frame.
#[derive(Clone, Debug)]
pub struct VertexBuffers {
    /// Per pixel: triangle + 1 (0 on background), bits of b1, bits of b2, 0.
    pub ids: Vec<[u32; 4]>,
    /// V per vertex and blocked rays per vertex.
    pub visibility: Vec<f32>,
    pub blocked: Vec<u32>,
}

impl VertexStage {
    pub(crate) fn new(fg: &FrameGpu) -> Result<VertexStage> {
        let ctx = fg.ctx;
        let vertex_count = fg.scene.vertices.len() as u32;
        // At least one element: wgpu has no empty bindings.
        let bytes = vertex_count.max(1) as u64 * 4;
        Ok(VertexStage {
            raster: BarycentricsPass::new(ctx)?,
            ids: BarycentricsPass::allocate(ctx, fg.gbuffer.width, fg.gbuffer.height),
            camera: barycentrics::camera_buffer(
                ctx,
                &crate::render::gbuffer::camera_uniform(fg.scene),
            ),
            trace: EnvTraceVertex::new(ctx)?,
            interp: EnvVertexInterp::new(ctx)?,
            vertex_count,
            visibility: readback::zeroed_storage(ctx, "vertex visibility", bytes),
            blocked: readback::zeroed_storage(ctx, "vertex blocked", bytes),
            sums: readback::zeroed_storage(ctx, "vertex sums", bytes * 2),
        })
    }

    /// barycentrics, then env_trace at the vertices (one dispatch per chunk of lights, `chunks`
    /// holding `vertex_count`), then env_vertex_interp into V.
    pub(crate) fn run(
        &self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        chunks: &[wgpu::Buffer],
        lights: &wgpu::Buffer,
        bvh: &BvhBuffers,
        ao: &wgpu::Buffer,
    ) -> Result<()> {
        timer.stage(fg.ctx, Stage::BARYCENTRICS, |enc| {
            self.raster
                .record(fg.ctx, enc, &fg.scene_gpu, &self.camera, &self.ids);
            Ok(())
        })?;
        let out = VertexOutputs {
            visibility: &self.visibility,
            blocked: &self.blocked,
            sums: &self.sums,
        };
        let mesh = VertexMesh {
            vertices: &fg.scene_gpu.vertices,
            vertex_count: fg.scene.vertices.len() as u32,
            bvh,
        };
        timer.stage(fg.ctx, Stage::ENV_TRACE, |enc| {
            for params in chunks {
                self.trace.record(fg.ctx, enc, &mesh, params, lights, &out);
            }
            Ok(())
        })?;
        timer.stage(fg.ctx, Stage::ENV_VERTEX_INTERP, |enc| {
            let inputs = InterpInputs {
                scene_indices: &fg.scene_gpu.indices,
                params: &chunks[0],
                ids: &self.ids,
                vertex_visibility: &self.visibility,
                ao,
            };
            self.interp
                .record(fg.ctx, enc, &fg.gbuffer, &inputs, &fg.visibility);
            Ok(())
        })
    }

    pub(crate) fn read(&self, fg: &FrameGpu) -> Result<VertexBuffers> {
        let bytes = self.vertex_count as u64 * 4;
        Ok(VertexBuffers {
            ids: barycentrics::read_back(fg.ctx, &self.ids)?,
            visibility: readback::read_buffer(fg.ctx, &self.visibility, bytes)?,
            blocked: readback::read_buffer(fg.ctx, &self.blocked, bytes)?,
        })
    }
}
