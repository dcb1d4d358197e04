//! env_split: split or keep every active quadtree cell; children and leaves appended with atomics.

use super::{groups, ComputeKernel, Dispatch, FrameGpu, LINE_WORKGROUP};
use crate::Result;

pub struct EnvSplit {
    kernel: ComputeKernel,
}

/// Buffers of one split dispatch.
pub struct EnvSplitIo<'a> {
    pub params: &'a wgpu::Buffer,
    pub cells: &'a wgpu::Buffer,
    pub counts: &'a wgpu::Buffer,
    pub cell_power: &'a wgpu::Buffer,
    pub next_cells: &'a wgpu::Buffer,
    pub leaves: &'a wgpu::Buffer,
    /// [next cells, leaves, 0, 0] as atomics.
    pub control: &'a wgpu::Buffer,
}

impl EnvSplit {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new(fg.ctx, "env_split", "main")? })
    }

    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, io: &EnvSplitIo, cell_count: u32) {
        self.kernel.dispatch(
            fg.ctx,
            enc,
            &[
                (0, io.params.as_entire_binding()),
                (1, io.cells.as_entire_binding()),
                (2, io.counts.as_entire_binding()),
                (3, io.cell_power.as_entire_binding()),
                (4, io.next_cells.as_entire_binding()),
                (5, io.leaves.as_entire_binding()),
                (6, io.control.as_entire_binding()),
            ],
            Dispatch::Direct([groups(cell_count, LINE_WORKGROUP[0]), 1, 1]),
        );
    }
}
