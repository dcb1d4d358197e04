//! env_trace: shadow rays from every G-buffer pixel (`main`) or every mesh vertex (`vertex`) to a
//! list of directional lights through the scene's BVH, into V (and the blocked-ray counts).

use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP, PIXEL_WORKGROUP};
use crate::gpu::readback;
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::render::bvh::Bvh;
use crate::render::gbuffer::GBuffer;
use crate::Result;

/// The BVH on the GPU (bindings 20 and 21 of every ray-casting env kernel).
pub(crate) struct BvhBuffers {
    pub(crate) nodes: wgpu::Buffer,
    pub(crate) triangles: wgpu::Buffer,
}

impl BvhBuffers {
    pub(crate) fn upload(ctx: &GpuContext, bvh: &Bvh) -> BvhBuffers {
        let tris = if bvh.triangles.is_empty() {
            vec![Default::default()]
        } else {
            bvh.triangles.clone()
        };
        BvhBuffers {
            nodes: readback::storage_buffer(
                ctx,
                "bvh nodes",
                &bvh.nodes,
                wgpu::BufferUsages::empty(),
            ),
            triangles: readback::storage_buffer(
                ctx,
                "bvh triangles",
                &tris,
                wgpu::BufferUsages::empty(),
            ),
        }
    }
}

pub(crate) struct EnvTrace {
    kernel: ComputeKernel,
}

/// The `vertex` entry point (the per-vertex variant), built only where a method asks for it.
pub(crate) struct EnvTraceVertex {
    kernel: ComputeKernel,
}

/// The mesh the per-vertex rays start from and test: its vertex buffer, its length and its BVH.
#[derive(Clone, Copy)]
pub(crate) struct VertexMesh<'a> {
    pub(crate) vertices: &'a wgpu::Buffer,
    pub(crate) vertex_count: u32,
    pub(crate) bvh: &'a BvhBuffers,
}

/// What the `vertex` entry point writes: V, blocked rays and running sums per vertex.
pub(crate) struct VertexOutputs<'a> {
    pub(crate) visibility: &'a wgpu::Buffer,
    pub(crate) blocked: &'a wgpu::Buffer,
    pub(crate) sums: &'a wgpu::Buffer,
}

/// What env_trace reads and writes besides the G-buffer and V.
pub(crate) struct EnvTraceInputs<'a> {
    pub(crate) params: &'a wgpu::Buffer,
    pub(crate) lights: &'a wgpu::Buffer,
    pub(crate) blocked: &'a wgpu::Buffer,
    /// Ambient occlusion per pixel (read when `params.use_ao` is 1; any buffer otherwise).
    pub(crate) ao: &'a wgpu::Buffer,
    /// Running sums between chunks, 8 bytes per pixel.
    pub(crate) sums: &'a wgpu::Buffer,
    pub(crate) bvh: &'a BvhBuffers,
}

/// Lights per env_trace dispatch (see kernels/env_trace.wgsl).
pub(crate) const ENV_TRACE_CHUNK: u32 = 256;

/// The per-chunk parameter blocks of `light_count` lights (at least one, which writes V).
pub(crate) fn chunk_params(
    base: &crate::gpu::structs::GpuEnvParams,
    light_count: u32,
) -> Vec<crate::gpu::structs::GpuEnvParams> {
    let chunks = light_count.div_ceil(ENV_TRACE_CHUNK).max(1);
    (0..chunks)
        .map(|c| {
            let mut p = *base;
            p.first_light = c * ENV_TRACE_CHUNK;
            p.light_count = ENV_TRACE_CHUNK.min(light_count - p.first_light.min(light_count));
            p.final_chunk = (c + 1 == chunks) as u32;
            p
        })
        .collect()
}

impl EnvTrace {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new(ctx, Stage::ENV_TRACE, "main")?,
        })
    }

    /// Writes `visibility` at every `gbuffer` pixel.
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        gbuffer: &GBuffer,
        inputs: &EnvTraceInputs,
        visibility: &wgpu::Buffer,
    ) {
        self.kernel.dispatch(
            ctx,
            enc,
            bind::env_trace::Main {
                params: inputs.params.as_entire_binding(),
                gbuffer_position: wgpu::BindingResource::TextureView(&gbuffer.position_view),
                gbuffer_normal: wgpu::BindingResource::TextureView(&gbuffer.normal_view),
                lights: inputs.lights.as_entire_binding(),
                visibility: visibility.as_entire_binding(),
                blocked: inputs.blocked.as_entire_binding(),
                ao: inputs.ao.as_entire_binding(),
                sums: inputs.sums.as_entire_binding(),
                bvh_nodes: inputs.bvh.nodes.as_entire_binding(),
                bvh_triangles: inputs.bvh.triangles.as_entire_binding(),
            },
            Dispatch::Direct([
                groups(gbuffer.width, PIXEL_WORKGROUP[0]),
                groups(gbuffer.height, PIXEL_WORKGROUP[1]),
                1,
            ]),
        );
    }
}

impl EnvTraceVertex {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new(ctx, Stage::ENV_TRACE, "vertex")?,
        })
    }

    /// One chunk of lights at every mesh vertex (`params.vertex_count` of them): `scene_vertices`
    /// is the scene's vertex buffer, `vertex_count` its length (the dispatch covers it).
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        mesh: &VertexMesh,
        params: &wgpu::Buffer,
        lights: &wgpu::Buffer,
        out: &VertexOutputs,
    ) {
        let VertexMesh {
            vertices: scene_vertices,
            vertex_count,
            bvh,
        } = *mesh;
        self.kernel.dispatch(
            ctx,
            enc,
            bind::env_trace::Vertex {
                params: params.as_entire_binding(),
                lights: lights.as_entire_binding(),
                blocked: out.blocked.as_entire_binding(),
                sums: out.sums.as_entire_binding(),
                scene_vertices: scene_vertices.as_entire_binding(),
                vertex_visibility: out.visibility.as_entire_binding(),
                bvh_nodes: bvh.nodes.as_entire_binding(),
                bvh_triangles: bvh.triangles.as_entire_binding(),
            },
            Dispatch::Direct([groups(vertex_count, LINE_WORKGROUP[0]), 1, 1]),
        );
    }
}
