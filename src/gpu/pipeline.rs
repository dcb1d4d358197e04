//! Pipelines are created inside a validation error scope so a bad kernel is a readable error.

use super::{GpuContext, Stage};
use crate::gpu::kernels;
use crate::gpu::kernels::MapAccess;
use crate::{Error, Result};

pub fn shader_module(ctx: &GpuContext, kernel: &str) -> Result<wgpu::ShaderModule> {
    shader_module_for(ctx, kernel, MapAccess::Depth)
}

/// The kernel built for one map access form (kernels::source_for).
pub fn shader_module_for(ctx: &GpuContext, kernel: &str, maps: MapAccess) -> Result<wgpu::ShaderModule> {
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
    compute_pipeline_for(ctx, kernel, entry, MapAccess::Depth)
}

pub fn compute_pipeline_for(ctx: &GpuContext, kernel: &str, entry: &str, maps: MapAccess) -> Result<wgpu::ComputePipeline> {
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

/// Bind group 0 of a render stage, its resources named by WGSL variable; the stage table gives
/// their bindings (the union of the stage's vertex and fragment entry points).
pub fn bind_group(
    ctx: &GpuContext,
    stage: Stage,
    layout: &wgpu::BindGroupLayout,
    resources: &[(&str, wgpu::BindingResource)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .map(|(name, r)| wgpu::BindGroupEntry {
            binding: stage.binding(name).unwrap_or_else(|| panic!("{stage} has no binding `{name}` (gpu::stages)")),
            resource: r.clone(),
        })
        .collect();
    ctx.device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(stage.name), layout, entries: &entries })
}
