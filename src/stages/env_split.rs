//! env_split: split or keep every active quadtree cell; children and leaves appended with atomics.

use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::Result;

pub(crate) struct EnvSplit {
    kernel: ComputeKernel,
}

/// Buffers of one split dispatch.
pub(crate) struct EnvSplitIo<'a> {
    pub(crate) params: &'a wgpu::Buffer,
    pub(crate) cells: &'a wgpu::Buffer,
    pub(crate) counts: &'a wgpu::Buffer,
    pub(crate) cell_power: &'a wgpu::Buffer,
    pub(crate) next_cells: &'a wgpu::Buffer,
    pub(crate) leaves: &'a wgpu::Buffer,
    /// [next cells, leaves, 0, 0] as atomics.
    pub(crate) control: &'a wgpu::Buffer,
}

impl EnvSplit {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new(ctx, Stage::ENV_SPLIT, "main")?,
        })
    }

    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        io: &EnvSplitIo,
        cell_count: u32,
    ) {
        self.kernel.dispatch(
            ctx,
            enc,
            bind::env_split::Main {
                params: io.params.as_entire_binding(),
                cells: io.cells.as_entire_binding(),
                counts: io.counts.as_entire_binding(),
                cell_power: io.cell_power.as_entire_binding(),
                next_cells: io.next_cells.as_entire_binding(),
                leaves: io.leaves.as_entire_binding(),
                control: io.control.as_entire_binding(),
            },
            Dispatch::Direct([groups(cell_count, LINE_WORKGROUP[0]), 1, 1]),
        );
    }
}
