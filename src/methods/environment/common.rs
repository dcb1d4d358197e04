//! What the environment methods share: the scene's BVH on both sides, the kernels' parameter
//! block, and the ssao stage (its own method, and a factor the others can multiply in).

use crate::gpu::readback;
use crate::gpu::stages::bind;
use crate::gpu::structs::{GpuCamera, GpuEnvCell, GpuEnvLight, GpuEnvParams};
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::render::bvh::Bvh;
use crate::scene::environment::{EnvLight, Environment};
use crate::stages::env_trace::BvhBuffers;
use crate::stages::ssao::hemisphere_kernel;
use crate::stages::ssao::Ssao;
use crate::stages::FrameGpu;
use crate::{Error, Result};
use std::sync::Arc;

pub(crate) fn environment<'a>(fg: &'a FrameGpu, method: &str) -> Result<&'a Environment> {
    fg.scene.environment.as_ref().ok_or_else(|| {
        Error::Param(format!(
            "{method}: scene `{}` has no [environment] (see docs/environment.md)",
            fg.scene.name
        ))
    })
}

/// The BVH, built once per scene and settings, kept on the CPU for the twins.
pub(crate) struct SceneRays {
    pub(crate) bvh: Arc<Bvh>,
    pub(crate) buffers: BvhBuffers,
    pub(crate) ray_offset: f32,
    pub(crate) t_max: f32,
}

impl SceneRays {
    pub(crate) fn build(fg: &FrameGpu) -> SceneRays {
        let bvh = Arc::new(Bvh::build(&fg.scene.triangles()));
        let buffers = BvhBuffers::upload(fg.ctx, &bvh);
        SceneRays {
            bvh,
            buffers,
            ray_offset: crate::scene::rays::ray_offset(fg.scene),
            t_max: crate::scene::rays::env_ray_length(fg.scene),
        }
    }

    pub(crate) fn params(&self, fg: &FrameGpu) -> GpuEnvParams {
        GpuEnvParams {
            width: fg.gbuffer.width,
            height: fg.gbuffer.height,
            ray_offset: self.ray_offset,
            t_max: self.t_max,
            ..Default::default()
        }
    }
}

pub(crate) fn gpu_lights(lights: &[EnvLight]) -> Vec<GpuEnvLight> {
    lights
        .iter()
        .map(|l| GpuEnvLight {
            direction: [l.direction.x, l.direction.y, l.direction.z, l.power],
        })
        .collect()
}

/// ssao: parameters, buffers and pass. AO lands in `ao` (1 = open).
pub(crate) struct SsaoStage {
    pub(crate) pass: Ssao,
    pub(crate) params: GpuEnvParams,
    pub(crate) camera: GpuCamera,
    pub(crate) kernel: Vec<[f32; 4]>,
    pub(crate) params_buffer: wgpu::Buffer,
    pub(crate) camera_buffer: wgpu::Buffer,
    pub(crate) kernel_buffer: wgpu::Buffer,
    pub(crate) ao: wgpu::Buffer,
    pub(crate) occluded: wgpu::Buffer,
}

/// ssao settings: samples per pixel and radius as a share of the scene's bounding-box diagonal.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SsaoSettings {
    pub(crate) samples: u32,
    pub(crate) radius: f32,
}

impl SsaoStage {
    pub(crate) fn new(fg: &FrameGpu, settings: SsaoSettings) -> Result<SsaoStage> {
        let s = fg.scene;
        let aspect = s.render.width as f32 / s.render.height as f32;
        let camera = GpuCamera {
            clip_from_world: s
                .camera
                .clip_from_world(aspect, &s.bounds)
                .to_cols_array_2d(),
            eye: s.camera.eye.extend(1.0).to_array(),
        };
        let diag = s.bounds.diagonal();
        let params = GpuEnvParams {
            width: fg.gbuffer.width,
            height: fg.gbuffer.height,
            light_count: settings.samples,
            radius: settings.radius * diag,
            // Depth tolerance: the surface itself must not occlude its own samples.
            ray_offset: 1e-3 * diag,
            ..Default::default()
        };
        let kernel = hemisphere_kernel(settings.samples);
        let ctx = fg.ctx;
        let bytes = fg.pixel_count() as u64 * 4;
        Ok(SsaoStage {
            pass: Ssao::new(ctx)?,
            params_buffer: readback::uniform_buffer(ctx, "ssao params", &params),
            camera_buffer: readback::uniform_buffer(ctx, "ssao camera", &camera),
            kernel_buffer: readback::storage_buffer(
                ctx,
                "ssao kernel",
                &kernel,
                wgpu::BufferUsages::empty(),
            ),
            ao: readback::zeroed_storage(ctx, "ao", bytes),
            occluded: readback::zeroed_storage(ctx, "ssao occluded", bytes),
            params,
            camera,
            kernel,
        })
    }

    pub(crate) fn run(&self, fg: &FrameGpu, timer: &mut StageTimer) -> Result<()> {
        timer.stage(fg.ctx, Stage::SSAO, |enc| {
            let g = &fg.gbuffer;
            let bindings = bind::ssao::Main {
                params: self.params_buffer.as_entire_binding(),
                camera: self.camera_buffer.as_entire_binding(),
                gbuffer_position: wgpu::BindingResource::TextureView(&g.position_view),
                gbuffer_normal: wgpu::BindingResource::TextureView(&g.normal_view),
                kernel: self.kernel_buffer.as_entire_binding(),
                ao: self.ao.as_entire_binding(),
                occluded: self.occluded.as_entire_binding(),
            };
            self.pass.record(fg.ctx, enc, bindings, [g.width, g.height]);
            Ok(())
        })
    }
}

/// `WxH` (a panorama resolution).
pub(crate) fn resolution(
    params: &crate::methods::ParamMap,
    method: &str,
    key: &str,
    default: (u32, u32),
) -> Result<(u32, u32)> {
    let Some(v) = params.get(key) else {
        return Ok(default);
    };
    let parsed = v
        .split_once('x')
        .and_then(|(a, b)| Some((a.trim().parse::<u32>().ok()?, b.trim().parse::<u32>().ok()?)));
    match parsed {
        Some((w, h)) if w >= 1 && h >= 1 && w <= 4096 && h <= 2048 => Ok((w, h)),
        _ => Err(Error::Param(format!(
            "{method}: {key} = `{v}`: give WxH, e.g. 32x16 (at most 4096x2048)"
        ))),
    }
}

/// One level of env-adaptive, kept for the twins.
#[derive(Clone, Debug)]
pub struct EnvLevelBuffers {
    pub params: GpuEnvParams,
    pub cells: Vec<GpuEnvCell>,
    pub counts: Vec<u32>,
    pub next: Vec<GpuEnvCell>,
    /// Leaves appended by this level.
    pub leaves: Vec<GpuEnvCell>,
    pub corners: Vec<[f32; 4]>,
    pub cell_power: Vec<f32>,
}
