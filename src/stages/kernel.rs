//! A compute entry point with its pipeline; bindings are given as (binding, resource) pairs so each
//! stage module states exactly what its kernel reads and writes.

use crate::gpu::{pipeline, GpuContext};
use crate::Result;

pub struct ComputeKernel {
    pub name: &'static str,
    pub entry: &'static str,
    pipeline: wgpu::ComputePipeline,
}

pub enum Dispatch<'a> {
    Direct([u32; 3]),
    Indirect(&'a wgpu::Buffer),
    /// Arguments at a byte offset of the buffer.
    IndirectAt(&'a wgpu::Buffer, u64),
}

impl ComputeKernel {
    pub fn new(ctx: &GpuContext, name: &'static str, entry: &'static str) -> Result<Self> {
        Self::new_for(ctx, name, entry, crate::scene::MapKind::Plain)
    }

    /// A map-reading kernel built for the scene's shadow-map representation.
    pub fn new_for(ctx: &GpuContext, name: &'static str, entry: &'static str, maps: crate::scene::MapKind) -> Result<Self> {
        Ok(Self { name, entry, pipeline: pipeline::compute_pipeline_for(ctx, name, entry, maps)? })
    }

    pub fn dispatch(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &[(u32, wgpu::BindingResource)],
        dispatch: Dispatch,
    ) {
        let entries: Vec<wgpu::BindGroupEntry> =
            bindings.iter().map(|(b, r)| wgpu::BindGroupEntry { binding: *b, resource: r.clone() }).collect();
        let bind = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.name),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.name), timestamp_writes: None });
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
