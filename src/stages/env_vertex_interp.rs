//! env_vertex_interp: V per pixel from V per mesh vertex, by the pixel's barycentrics
//! (env-pixels:at=vertex).

use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::render::barycentrics::TriangleIds;
use crate::render::gbuffer::GBuffer;
use crate::Result;

/// What the interpolation reads: the scene's indices, the parameters, each pixel's triangle and
/// barycentrics, the per-vertex visibility and AO.
#[derive(Clone, Copy)]
pub(crate) struct InterpInputs<'a> {
    pub(crate) scene_indices: &'a wgpu::Buffer,
    pub(crate) params: &'a wgpu::Buffer,
    pub(crate) ids: &'a TriangleIds,
    pub(crate) vertex_visibility: &'a wgpu::Buffer,
    pub(crate) ao: &'a wgpu::Buffer,
}

pub(crate) struct EnvVertexInterp {
    kernel: ComputeKernel,
}

impl EnvVertexInterp {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new(ctx, Stage::ENV_VERTEX_INTERP, "main")?,
        })
    }

    /// `ao` is read when `params.use_ao` is 1 (any buffer otherwise); `scene_indices` is the scene's
    /// index buffer (the ids name its triangles); `gbuffer` sizes the dispatch.
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        gbuffer: &GBuffer,
        inputs: &InterpInputs,
        visibility: &wgpu::Buffer,
    ) {
        let InterpInputs {
            scene_indices,
            params,
            ids,
            vertex_visibility,
            ao,
        } = *inputs;
        self.kernel.dispatch(
            ctx,
            enc,
            bind::env_vertex_interp::Main {
                params: params.as_entire_binding(),
                triangle_ids: wgpu::BindingResource::TextureView(&ids.view),
                scene_indices: scene_indices.as_entire_binding(),
                vertex_visibility: vertex_visibility.as_entire_binding(),
                ao: ao.as_entire_binding(),
                visibility: visibility.as_entire_binding(),
            },
            Dispatch::Direct([
                groups(gbuffer.width, PIXEL_WORKGROUP[0]),
                groups(gbuffer.height, PIXEL_WORKGROUP[1]),
                1,
            ]),
        );
    }
}
