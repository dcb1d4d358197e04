//! env_shadowmaps: PCF (the pcf family's tap patterns) over K directional lights' shadow maps,
//! power- and cosine-weighted.

use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::kernels::MapAccess;
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::render::gbuffer::GBuffer;
use crate::Result;

pub(crate) struct EnvShadowmaps {
    kernel: ComputeKernel,
    /// The comparison sampler of `filter=bilinear`, as pcf's.
    sampler: wgpu::Sampler,
}

/// What the kernel reads besides the G-buffer: the method's frame uniform and parameters, one
/// sample and map per light, the lights, AO and the PCF filter.
#[derive(Clone, Copy)]
pub(crate) struct EnvMapInputs<'a> {
    pub(crate) frame: &'a wgpu::Buffer,
    pub(crate) params: &'a wgpu::Buffer,
    pub(crate) samples: &'a wgpu::Buffer,
    pub(crate) maps: &'a wgpu::TextureView,
    pub(crate) lights: &'a wgpu::Buffer,
    pub(crate) ao: &'a wgpu::Buffer,
    pub(crate) filter: FilterBuffers<'a>,
}

/// The filter's uniform and tap offsets (the pcf family's `GpuFilter` and disk).
#[derive(Clone, Copy)]
pub(crate) struct FilterBuffers<'a> {
    pub(crate) settings: &'a wgpu::Buffer,
    pub(crate) disk: &'a wgpu::Buffer,
}

impl EnvShadowmaps {
    /// `raster`: how the raster's layers are read (`Raster::raster_access`).
    pub(crate) fn new(ctx: &GpuContext, raster: MapAccess) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new_for(ctx, Stage::ENV_SHADOWMAPS, "main", raster)?,
            sampler: super::pcf::comparison_sampler(ctx),
        })
    }

    /// `frame` is the method's own frame uniform (its light-side plane passes every point); `ao` is read
    /// when `params.use_ao` is 1. Writes `visibility` at every `gbuffer` pixel.
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        gbuffer: &GBuffer,
        inputs: &EnvMapInputs,
        visibility: &wgpu::Buffer,
    ) {
        let EnvMapInputs {
            frame,
            params,
            samples,
            maps,
            lights,
            ao,
            filter,
        } = *inputs;
        self.kernel.dispatch(
            ctx,
            enc,
            bind::env_shadowmaps::Main {
                frame: frame.as_entire_binding(),
                params: params.as_entire_binding(),
                samples: samples.as_entire_binding(),
                gbuffer_position: wgpu::BindingResource::TextureView(&gbuffer.position_view),
                gbuffer_normal: wgpu::BindingResource::TextureView(&gbuffer.normal_view),
                shadow_maps: wgpu::BindingResource::TextureView(maps),
                lights: lights.as_entire_binding(),
                visibility: visibility.as_entire_binding(),
                ao: ao.as_entire_binding(),
                settings: filter.settings.as_entire_binding(),
                disk: filter.disk.as_entire_binding(),
                compare_sampler: wgpu::BindingResource::Sampler(&self.sampler),
            },
            Dispatch::Direct([
                groups(gbuffer.width, PIXEL_WORKGROUP[0]),
                groups(gbuffer.height, PIXEL_WORKGROUP[1]),
                1,
            ]),
        );
    }
}
