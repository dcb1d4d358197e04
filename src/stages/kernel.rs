//! A compute entry point with its pipeline. Its bindings are one struct generated from the stage
//! table (`gpu::stages::bind`, checked against the kernels by tests/kernels.rs), with a field per
//! WGSL variable, so each stage module states exactly what its kernel reads and writes, the
//! compiler rejects a missing or misspelled binding, and no index is written twice.

use crate::gpu::kernels::MapAccess;
use crate::gpu::stages::{Bindings, Entry, Stage};
use crate::gpu::{pipeline, GpuContext};
use crate::{Error, Result};

pub(crate) struct ComputeKernel {
    pub(crate) stage: Stage,
    pub(crate) entry: &'static Entry,
    pipeline: wgpu::ComputePipeline,
}

pub(crate) enum Dispatch<'a> {
    Direct([u32; 3]),
    Indirect(&'a wgpu::Buffer),
    /// Arguments at a byte offset of the buffer.
    IndirectAt(&'a wgpu::Buffer, u64),
}

impl ComputeKernel {
    pub(crate) fn new(ctx: &GpuContext, stage: Stage, entry: &str) -> Result<Self> {
        Self::new_for(ctx, stage, entry, MapAccess::Depth)
    }

    /// A map-reading kernel built for one map access form (`FrameGpu::map_access`).
    pub(crate) fn new_for(
        ctx: &GpuContext,
        stage: Stage,
        entry: &str,
        maps: MapAccess,
    ) -> Result<Self> {
        let table = stage.entry(entry).ok_or_else(|| Error::Kernel {
            name: stage.name.into(),
            message: format!("no entry point `{entry}` in the stage table"),
        })?;
        Ok(Self {
            stage,
            entry: table,
            pipeline: pipeline::compute_pipeline_for(ctx, stage.name, entry, maps)?,
        })
    }

    /// Records one dispatch of this entry point with its bindings (`bind::<stage>::<Set>`, generated
    /// from the stage table: the compiler checks that every variable is bound, once, by its name).
    pub(crate) fn dispatch<'a, B: Bindings<'a>>(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        bindings: B,
        dispatch: Dispatch,
    ) {
        // The struct must be this entry point's: another's would bind another layout.
        assert!(
            B::STAGE == self.stage.name && B::ENTRY_POINTS.contains(&self.entry.name),
            "{}::{} bound with the bindings of {}::{:?}",
            self.stage,
            self.entry.name,
            B::STAGE,
            B::ENTRY_POINTS
        );
        let entries = bindings.entries();
        let bind = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.stage.name),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(self.stage.name),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        match dispatch {
            Dispatch::Direct([x, y, z]) => {
                if x > 0 && y > 0 && z > 0 {
                    pass.dispatch_workgroups(x, y, z)
                }
            }
            Dispatch::Indirect(args) => pass.dispatch_workgroups_indirect(args, 0),
            Dispatch::IndirectAt(args, offset) => pass.dispatch_workgroups_indirect(args, offset),
        }
    }
}
