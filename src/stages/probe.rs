//! probe (scope = local): uniform pixels of split quads read the quads' new samples' lit bits
//! (shadow_test `probes` cached them); agreement adds the uniform share, disagreement makes the
//! pixel four child items of this level.

use crate::methods::adaptive::buffers::AdaptiveBuffers;
use super::{ComputeKernel, Dispatch};
use super::FrameGpu;
use crate::Result;

pub struct Probe {
    main: ComputeKernel,
    begin: ComputeKernel,
}

impl Probe {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { main: ComputeKernel::new(fg.ctx, "probe", "main")?, begin: ComputeKernel::new(fg.ctx, "probe", "begin")? })
    }

    /// Makes the probes compact appended this level's work (their count and dispatch size).
    pub fn record_begin(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, level: &wgpu::Buffer) {
        self.begin.dispatch(
            fg.ctx,
            enc,
            &[
                (1, level.as_entire_binding()),
                (10, b.control.as_entire_binding()),
                (13, b.probe_total.as_entire_binding()),
                (14, b.probe_args.as_entire_binding()),
            ],
            Dispatch::Direct([1, 1, 1]),
        );
    }

    /// `quads`: this level's quads (the probed parents' children); `items`: this level's item list.
    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, level: &wgpu::Buffer, quads: &wgpu::Buffer, items: &wgpu::Buffer) {
        self.main.dispatch(
            fg.ctx,
            enc,
            &[
                (1, level.as_entire_binding()),
                (2, b.probes.as_entire_binding()),
                (3, quads.as_entire_binding()),
                (4, b.masks.as_entire_binding()),
                (9, items.as_entire_binding()),
                (10, b.control.as_entire_binding()),
                (11, b.visibility_fixed.as_entire_binding()),
                (13, b.probe_total.as_entire_binding()),
            ],
            Dispatch::Indirect(&b.probe_args),
        );
    }
}
