//! A compute entry point with its pipeline. Bindings are given by the WGSL variable's name, and
//! the stage table (`gpu::stages`, checked against the kernels by tests/kernels.rs) gives their
//! indices, so each stage module states exactly what its kernel reads and writes and no index is
//! written twice.

use crate::gpu::kernels::MapAccess;
use crate::gpu::stages::{Entry, Stage};
use crate::gpu::{pipeline, GpuContext};
use crate::{Error, Result};

pub struct ComputeKernel {
    pub stage: Stage,
    pub entry: &'static Entry,
    pipeline: wgpu::ComputePipeline,
}

pub enum Dispatch<'a> {
    Direct([u32; 3]),
    Indirect(&'a wgpu::Buffer),
    /// Arguments at a byte offset of the buffer.
    IndirectAt(&'a wgpu::Buffer, u64),
}

impl ComputeKernel {
    pub fn new(ctx: &GpuContext, stage: Stage, entry: &str) -> Result<Self> {
        Self::new_for(ctx, stage, entry, MapAccess::Depth)
    }

    /// A map-reading kernel built for one map access form (`FrameGpu::map_access`).
    pub fn new_for(ctx: &GpuContext, stage: Stage, entry: &str, maps: MapAccess) -> Result<Self> {
        let table = stage.entry(entry).ok_or_else(|| Error::Kernel { name: stage.name.into(), message: format!("no entry point `{entry}` in the stage table") })?;
        Ok(Self { stage, entry: table, pipeline: pipeline::compute_pipeline_for(ctx, stage.name, entry, maps)? })
    }

    /// The @binding of the WGSL variable `name`. A name the entry point does not use is a bug in
    /// the pass (the stage table lists every binding naga finds), so it panics.
    pub fn binding(&self, name: &str) -> u32 {
        self.entry.binding(name).unwrap_or_else(|| panic!("{}::{} has no binding `{name}` (gpu::stages)", self.stage, self.entry.name))
    }

    pub fn dispatch(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &[(&str, wgpu::BindingResource)],
        dispatch: Dispatch,
    ) {
        let entries: Vec<wgpu::BindGroupEntry> =
            bindings.iter().map(|(b, r)| wgpu::BindGroupEntry { binding: self.binding(b), resource: r.clone() }).collect();
        // The layout is the entry point's own: every variable it uses must be bound.
        assert_eq!(
            entries.len(),
            self.entry.bindings.len(),
            "{}::{} binds {:?}, the kernel uses {:?}",
            self.stage,
            self.entry.name,
            entries.iter().map(|e| e.binding).collect::<Vec<_>>(),
            self.entry.bindings
        );
        let bind = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.stage.name),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.stage.name), timestamp_writes: None });
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
