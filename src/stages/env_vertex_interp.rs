//! env_vertex_interp: V per pixel from V per mesh vertex, by the pixel's barycentrics
//! (env-pixels:at=vertex).

use crate::gpu::Stage;
use super::{groups, ComputeKernel, Dispatch, FrameGpu, PIXEL_WORKGROUP};
use crate::render::barycentrics::TriangleIds;
use crate::Result;

pub struct EnvVertexInterp {
    kernel: ComputeKernel,
}

impl EnvVertexInterp {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new(fg.ctx, Stage::ENV_VERTEX_INTERP, "main")? })
    }

    /// `ao` is read when `params.use_ao` is 1 (any buffer otherwise).
    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, params: &wgpu::Buffer, ids: &TriangleIds, vertex_visibility: &wgpu::Buffer, ao: &wgpu::Buffer) {
        self.kernel.dispatch(
            fg.ctx,
            enc,
            &[
                ("params", params.as_entire_binding()),
                ("triangle_ids", wgpu::BindingResource::TextureView(&ids.view)),
                ("scene_indices", fg.scene_gpu.indices.as_entire_binding()),
                ("vertex_visibility", vertex_visibility.as_entire_binding()),
                ("ao", ao.as_entire_binding()),
                ("visibility", fg.visibility.as_entire_binding()),
            ],
            Dispatch::Direct([groups(fg.gbuffer.width, PIXEL_WORKGROUP[0]), groups(fg.gbuffer.height, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
