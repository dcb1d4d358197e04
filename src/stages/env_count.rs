//! env_count: per active quadtree cell, the pixels whose rays to the cell's corners disagree.

use super::env_trace::BvhBuffers;
use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::render::gbuffer::GBuffer;
use crate::Result;

/// One level's count: its parameters, the corner rays, `cell_count` cells and their counts, over
/// every `stride`-th pixel.
#[derive(Clone, Copy)]
pub(crate) struct EnvCountInputs<'a> {
    pub(crate) params: &'a wgpu::Buffer,
    pub(crate) corners: &'a wgpu::Buffer,
    pub(crate) cells: &'a wgpu::Buffer,
    pub(crate) counts: &'a wgpu::Buffer,
    pub(crate) cell_count: u32,
    pub(crate) stride: u32,
}

pub(crate) struct EnvCount {
    kernel: ComputeKernel,
}

impl EnvCount {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new(ctx, Stage::ENV_COUNT, "main")?,
        })
    }

    /// `counts` must be zeroed for the `cells` active cells.
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        gbuffer: &GBuffer,
        inputs: &EnvCountInputs,
        bvh: &BvhBuffers,
    ) {
        let EnvCountInputs {
            params,
            corners,
            cells,
            counts,
            cell_count,
            stride,
        } = *inputs;
        self.kernel.dispatch(
            ctx,
            enc,
            bind::env_count::Main {
                params: params.as_entire_binding(),
                gbuffer_position: wgpu::BindingResource::TextureView(&gbuffer.position_view),
                gbuffer_normal: wgpu::BindingResource::TextureView(&gbuffer.normal_view),
                corners: corners.as_entire_binding(),
                cells: cells.as_entire_binding(),
                counts: counts.as_entire_binding(),
                bvh_nodes: bvh.nodes.as_entire_binding(),
                bvh_triangles: bvh.triangles.as_entire_binding(),
            },
            Dispatch::Direct([
                groups(
                    counted_pixels(gbuffer.width, gbuffer.height, stride),
                    LINE_WORKGROUP[0],
                ),
                cell_count,
                1,
            ]),
        );
    }
}

/// Pixels counted with every `stride`-th pixel in x and y.
pub(crate) fn counted_pixels(width: u32, height: u32, stride: u32) -> u32 {
    let s = stride.max(1);
    width.div_ceil(s) * height.div_ceil(s)
}
