//! One frame: upload, G-buffer, the method's shadow maps and compute stages, read-back.

use crate::compute::shade::{ShadeInputs, ShadePass};
use crate::gpu::{readback, GpuContext};
use crate::layout::{GpuCamera, GpuFrame};
use crate::methods::{self, Method};
use crate::render::gbuffer::{self, GBuffer, GBufferCpu, GBufferPass};
use crate::render::shadow_raster::ShadowRasterPass;
use crate::render::SceneGpu;
use crate::scene::Scene;
use crate::timing::{StageTimer, TimingMode};
use crate::Result;
use std::collections::BTreeMap;
use std::time::Instant;

/// What a method hands back besides the visibility buffer it filled.
pub struct MethodOutput {
    pub shadow_maps: u32,
    /// CPU↔GPU synchronisations the algorithm needs (read-backs), not counting timing waits.
    pub syncs: u32,
    pub record: serde_json::Value,
    pub pictures: Vec<(String, image::RgbImage)>,
}

/// GPU state every method works on.
pub struct FrameGpu<'a> {
    pub ctx: &'a GpuContext,
    pub scene: &'a Scene,
    pub scene_gpu: SceneGpu,
    pub gbuffer: GBuffer,
    pub frame: GpuFrame,
    pub frame_buffer: wgpu::Buffer,
    pub raster: ShadowRasterPass,
    pub shade: ShadePass,
    pub visibility: wgpu::Buffer,
    /// Whether methods read back what their pictures need (off for timed benchmark runs).
    pub pictures: bool,
}

/// How to run a frame.
#[derive(Clone, Copy, Debug)]
pub struct FrameOptions {
    pub mode: TimingMode,
    /// Read back the decision pictures (comparison map, flags, samples per pixel): this makes the
    /// per-level read-back larger, so timed runs turn it off.
    pub pictures: bool,
}

impl FrameGpu<'_> {
    pub fn shade_inputs<'b>(&'b self, samples: &'b wgpu::Buffer, weights: &'b wgpu::Buffer) -> ShadeInputs<'b> {
        ShadeInputs { frame: &self.frame_buffer, samples, weights, gbuffer: &self.gbuffer, visibility: &self.visibility }
    }
    pub fn pixel_count(&self) -> u32 {
        self.gbuffer.width * self.gbuffer.height
    }
}

pub struct FrameResult {
    pub visibility: Vec<f32>,
    pub gbuffer: GBufferCpu,
    pub output: MethodOutput,
    pub stages_ms: BTreeMap<String, f64>,
    pub total_ms: f64,
    pub timing_waits: u32,
    /// GPU timestamps per stage, where the adapter's are trusted; None otherwise.
    pub gpu_stages_ms: Option<BTreeMap<String, f64>>,
}

pub fn frame_uniform(scene: &Scene) -> GpuFrame {
    let b = scene.render.bias;
    GpuFrame {
        width: scene.render.width,
        height: scene.render.height,
        map_size: scene.render.shadow_map_size,
        flags: if scene.render.self_shadow == crate::scene::SelfShadow::Facing { 1 } else { 0 },
        light_center: [scene.light.center.x, scene.light.center.y, scene.light.center.z, 1.0],
        light_normal: scene.light.normal().extend(0.0).to_array(),
        bias_constant: b.constant,
        bias_slope: b.slope,
        normal_offset: b.normal_offset,
        max_slope: b.max_slope,
    }
}

pub fn camera_uniform(scene: &Scene) -> GpuCamera {
    let aspect = scene.render.width as f32 / scene.render.height as f32;
    GpuCamera {
        clip_from_world: scene.camera.clip_from_world(aspect, &scene.bounds).to_cols_array_2d(),
        eye: scene.camera.eye.extend(1.0).to_array(),
    }
}

/// Renders one frame of `scene` with `method`, pictures included.
pub fn render(ctx: &GpuContext, scene: &Scene, method: &Method, mode: TimingMode) -> Result<FrameResult> {
    render_with(ctx, scene, method, FrameOptions { mode, pictures: true }, &mut None, false)
}

/// Renders one frame with explicit options (benchmarks: `pictures: false`).
pub fn render_with_options(ctx: &GpuContext, scene: &Scene, method: &Method, options: FrameOptions) -> Result<FrameResult> {
    render_with(ctx, scene, method, options, &mut None, false)
}

fn render_with(
    ctx: &GpuContext,
    scene: &Scene,
    method: &Method,
    options: FrameOptions,
    trace: &mut Option<methods::adaptive::AdaptiveTrace>,
    capture: bool,
) -> Result<FrameResult> {
    render_inner(ctx, scene, method, options, trace, capture, None)
}

/// Renders with a fixed-sample method (hard, regular), keeping every map for the shade twin.
pub fn render_fixed_captured(ctx: &GpuContext, scene: &Scene, method: &Method) -> Result<(FrameResult, methods::fixed::FixedCapture)> {
    let mut c = methods::fixed::FixedCapture::default();
    let r = render_inner(ctx, scene, method, FrameOptions { mode: TimingMode::Frame, pictures: true }, &mut None, false, Some(&mut c))?;
    Ok((r, c))
}

fn render_inner(
    ctx: &GpuContext,
    scene: &Scene,
    method: &Method,
    options: FrameOptions,
    trace: &mut Option<methods::adaptive::AdaptiveTrace>,
    capture: bool,
    fixed_capture: Option<&mut methods::fixed::FixedCapture>,
) -> Result<FrameResult> {
    let start = Instant::now();
    let mut timer = StageTimer::new(options.mode).with_gpu_timestamps(ctx);
    let (w, h) = (scene.render.width, scene.render.height);
    let gbuffer_pass = GBufferPass::new(ctx)?;
    let gbuffer = GBufferPass::allocate(ctx, w, h)?;
    let scene_gpu = timer.cpu("upload", || Ok(SceneGpu::upload(ctx, scene)))?;
    let frame = frame_uniform(scene);
    let fg = FrameGpu {
        ctx,
        scene,
        frame_buffer: readback::uniform_buffer(ctx, "frame", &frame),
        frame,
        raster: ShadowRasterPass::new(ctx, scene.render.cull)?,
        shade: ShadePass::new(ctx)?,
        visibility: readback::zeroed_storage(ctx, "visibility", w as u64 * h as u64 * 4),
        scene_gpu,
        gbuffer,
        pictures: options.pictures,
    };
    // Method buffers, arrays and pipelines are made (and zero-filled) before the clock starts.
    enum Prepared {
        Fixed(methods::fixed::Prepared),
        Adaptive(methods::AdaptiveParams, methods::adaptive::Prepared),
    }
    let prepared = match method {
        Method::Hard => Prepared::Fixed(methods::fixed::prepare(&fg, &[(0.5, 0.5)])?),
        Method::Regular { n, layout } => Prepared::Fixed(methods::fixed::prepare(&fg, &methods::fixed::regular_points(*n, *layout))?),
        Method::Adaptive(p) => Prepared::Adaptive(p.clone(), methods::adaptive::prepare(&fg, p)?),
    };
    ctx.wait()?;
    let setup_ms = start.elapsed().as_secs_f64() * 1e3;
    let frame_start = Instant::now();
    let camera = camera_uniform(scene);
    timer.stage(ctx, "gbuffer", |enc| {
        gbuffer_pass.record(ctx, enc, &fg.scene_gpu, &camera, &fg.gbuffer);
        Ok(())
    })?;
    let output = match prepared {
        Prepared::Adaptive(p, prep) => {
            let (out, t) = methods::adaptive::run(&fg, &mut timer, &p, prep, capture)?;
            *trace = Some(t);
            out
        }
        Prepared::Fixed(prep) => methods::fixed::run(&fg, &mut timer, prep, fixed_capture)?,
    };
    timer.flush(ctx);
    let mut visibility: Vec<f32> = timer.cpu("readback", || readback::read_buffer(ctx, &fg.visibility, w as u64 * h as u64 * 4))?;
    let total_ms = frame_start.elapsed().as_secs_f64() * 1e3;
    let gbuffer = gbuffer::read_back(ctx, &fg.gbuffer)?;
    // Σŵ = 1 up to rounding: clamp so V ∈ [0, 1] holds exactly; background stays 0.
    for (i, v) in visibility.iter_mut().enumerate() {
        *v = if gbuffer.is_geometry(i) { v.clamp(0.0, 1.0) } else { 0.0 };
    }
    let mut stages_ms = timer.stages_ms.clone();
    stages_ms.insert("setup".into(), setup_ms);
    let gpu_stages_ms = timer.gpu_stages_ms(ctx)?;
    Ok(FrameResult { visibility, gbuffer, output, stages_ms, total_ms, timing_waits: timer.timing_waits, gpu_stages_ms })
}

/// Renders with the adaptive method and returns its trace too; `capture` keeps every intermediate
/// buffer for the CPU twins (tests only: it adds read-backs).
pub fn render_traced(
    ctx: &GpuContext,
    scene: &Scene,
    p: &methods::AdaptiveParams,
    capture: bool,
) -> Result<(FrameResult, methods::adaptive::AdaptiveTrace)> {
    let mut trace = Some(methods::adaptive::AdaptiveTrace::default());
    let r = render_with(ctx, scene, &Method::Adaptive(p.clone()), FrameOptions { mode: TimingMode::Frame, pictures: true }, &mut trace, capture)?;
    Ok((r, trace.unwrap_or_default()))
}

/// Only the camera G-buffer of `scene`: what the CPU reference traces from. Same pass, same
/// uniforms as `render`, so its pixels are the points every method shades.
pub fn gbuffer_only(ctx: &GpuContext, scene: &Scene) -> Result<GBufferCpu> {
    let pass = GBufferPass::new(ctx)?;
    let target = GBufferPass::allocate(ctx, scene.render.width, scene.render.height)?;
    let scene_gpu = SceneGpu::upload(ctx, scene);
    let mut encoder = ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("gbuffer") });
    pass.record(ctx, &mut encoder, &scene_gpu, &camera_uniform(scene), &target);
    ctx.queue.submit([encoder.finish()]);
    gbuffer::read_back(ctx, &target)
}
