//! Pipelines are created inside a validation error scope so a bad kernel is a readable error.

use super::GpuContext;
use crate::gpu::kernels;
use crate::gpu::kernels::MapAccess;
use crate::gpu::stages::Bindings;
use crate::{Error, Result};

pub(crate) fn shader_module(ctx: &GpuContext, kernel: &str) -> Result<wgpu::ShaderModule> {
    shader_module_for(ctx, kernel, MapAccess::Depth)
}

/// The kernel built for one map access form (kernels::source_for).
pub(crate) fn shader_module_for(
    ctx: &GpuContext,
    kernel: &str,
    maps: MapAccess,
) -> Result<wgpu::ShaderModule> {
    let src = kernels::source_for(kernel, maps)?;
    let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = ctx
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(kernel),
            source: wgpu::ShaderSource::Wgsl(src.into()),
        });
    check(scope, kernel)?;
    Ok(module)
}

pub(crate) fn compute_pipeline_for(
    ctx: &GpuContext,
    kernel: &str,
    entry: &str,
    maps: MapAccess,
) -> Result<wgpu::ComputePipeline> {
    let module = shader_module_for(ctx, kernel, maps)?;
    let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let pipeline = ctx
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
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

pub(crate) fn check(scope: wgpu::ErrorScopeGuard, what: &str) -> Result<()> {
    match pollster::block_on(scope.pop()) {
        None => Ok(()),
        Some(e) => Err(Error::Kernel {
            name: what.into(),
            message: e.to_string().replace('\n', " "),
        }),
    }
}

/// Bind group 0 of a render stage from its generated struct (`bind::<stage>::Pipeline`: the union
/// of the stage's vertex and fragment entry points' bindings, by WGSL variable).
pub(crate) fn bind_group<'a, B: Bindings<'a>>(
    ctx: &GpuContext,
    layout: &wgpu::BindGroupLayout,
    bindings: B,
) -> wgpu::BindGroup {
    ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(B::STAGE),
        layout,
        entries: &bindings.entries(),
    })
}
