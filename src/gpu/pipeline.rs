//! Pipelines are created inside a validation error scope so a bad kernel is a readable error.

use super::GpuContext;
use crate::scene::MapKind;
use crate::gpu::kernels;
use crate::{Error, Result};

pub fn shader_module(ctx: &GpuContext, kernel: &str) -> Result<wgpu::ShaderModule> {
    shader_module_for(ctx, kernel, MapKind::Plain)
}

/// The kernel built for one shadow-map representation (kernels::source_for).
pub fn shader_module_for(ctx: &GpuContext, kernel: &str, maps: MapKind) -> Result<wgpu::ShaderModule> {
    let src = kernels::source_for(kernel, maps)?;
    let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = ctx.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(kernel),
        source: wgpu::ShaderSource::Wgsl(src.into()),
    });
    check(scope, kernel)?;
    Ok(module)
}

pub fn compute_pipeline(ctx: &GpuContext, kernel: &str, entry: &str) -> Result<wgpu::ComputePipeline> {
    compute_pipeline_for(ctx, kernel, entry, MapKind::Plain)
}

pub fn compute_pipeline_for(ctx: &GpuContext, kernel: &str, entry: &str, maps: MapKind) -> Result<wgpu::ComputePipeline> {
    let module = shader_module_for(ctx, kernel, maps)?;
    let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let pipeline = ctx.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(kernel),
        layout: None,
        module: &module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    });
    check(scope, kernel)?;
    Ok(pipeline)
}

pub fn check(scope: wgpu::ErrorScopeGuard, what: &str) -> Result<()> {
    match pollster::block_on(scope.pop()) {
        None => Ok(()),
        Some(e) => Err(Error::Kernel { name: what.into(), message: e.to_string().replace('\n', " ") }),
    }
}

/// Bind group from a list of resources at bindings 0, 1, 2, … of group 0.
pub fn bind_group(
    ctx: &GpuContext,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .enumerate()
        .map(|(i, r)| wgpu::BindGroupEntry { binding: i as u32, resource: r.clone() })
        .collect();
    ctx.device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(label), layout, entries: &entries })
}
