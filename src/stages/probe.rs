//! probe (scope = local): uniform pixels of split quads read the quads' new samples' lit bits
//! (shadow_test `probes` cached them); agreement adds the uniform share, disagreement makes the
//! pixel four child items of this level.

use super::{ComputeKernel, Dispatch};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::stages::adaptive_buffers::{ItemLists, Level, Masks};
use crate::Result;

pub struct Probe {
    main: ComputeKernel,
    begin: ComputeKernel,
}

impl Probe {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            main: ComputeKernel::new(ctx, Stage::PROBE, "main")?,
            begin: ComputeKernel::new(ctx, Stage::PROBE, "begin")?,
        })
    }

    /// Makes the probes compact appended this level's work (their count and dispatch size).
    pub fn record_begin(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        level: &wgpu::Buffer,
        control: &wgpu::Buffer,
        items: &ItemLists,
    ) {
        self.begin.dispatch(
            ctx,
            enc,
            bind::probe::Begin {
                level: level.as_entire_binding(),
                control: control.as_entire_binding(),
                probe_total: items.probe_total.as_entire_binding(),
                probe_args: items.probe_args.as_entire_binding(),
            },
            Dispatch::Direct([1, 1, 1]),
        );
    }

    /// `lv.quads`: this level's quads (the probed parents' children); `items.items[cur]`: this level's item list.
    pub fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        lv: &Level,
        masks: &Masks,
        items: &ItemLists,
    ) {
        let (control, cur) = (lv.control, lv.cur);
        self.main.dispatch(
            ctx,
            enc,
            bind::probe::Main {
                level: lv.uniform.as_entire_binding(),
                probes: items.probes.as_entire_binding(),
                quads: lv.quads.as_entire_binding(),
                masks: masks.lit.as_entire_binding(),
                items: items.items[cur].as_entire_binding(),
                control: control.as_entire_binding(),
                visibility_fixed: items.visibility_fixed.as_entire_binding(),
                probe_total: items.probe_total.as_entire_binding(),
            },
            Dispatch::Indirect(&items.probe_args),
        );
    }
}
