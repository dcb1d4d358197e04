//! truth_trace: the reference's own integrator at a list of surface points, one workgroup per
//! point (kernels/truth_trace.wgsl). The lab's CPU reference at the same pixels is its twin
//! (lab/tests/truth_trace.rs).

use super::{ComputeKernel, Dispatch};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::Result;

pub(crate) struct TruthTrace {
    kernel: ComputeKernel,
}

/// Workgroups for `count` points, one each: as many as one dimension takes, then rows of them
/// (the kernel reads its point as `wid.y · groups.x + wid.x`).
pub(crate) fn dispatch_size(count: u32, per_dimension: u32) -> [u32; 3] {
    let per_dimension = per_dimension.max(1);
    if count <= per_dimension {
        [count, 1, 1]
    } else {
        [per_dimension, count.div_ceil(per_dimension), 1]
    }
}

impl TruthTrace {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new(ctx, Stage::TRUTH_TRACE, "main")?,
        })
    }

    /// Records one chunk: `count` points from the params' `first`.
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        bindings: bind::truth_trace::Main,
        count: u32,
    ) {
        let size = dispatch_size(count, ctx.limits().max_compute_workgroups_per_dimension);
        self.kernel
            .dispatch(ctx, enc, bindings, Dispatch::Direct(size));
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn dispatch_covers_every_point_once() {
        assert_eq!(super::dispatch_size(7, 65535), [7, 1, 1]);
        assert_eq!(super::dispatch_size(65535, 65535), [65535, 1, 1]);
        // 2 rows of 65535 cover 65536; the kernel skips the rest of the second row.
        assert_eq!(super::dispatch_size(65536, 65535), [65535, 2, 1]);
        assert_eq!(super::dispatch_size(0, 65535), [0, 1, 1]);
    }
}
