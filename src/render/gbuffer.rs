//! gbuffer: camera raster of world position and camera-facing normal, one texel per pixel.

use super::{vertex_layout, SceneGpu, VERTEX_ATTRIBUTES};
use crate::gpu::stages::bind;
use crate::gpu::structs::GpuCamera;
use crate::gpu::{pipeline, readback, GpuContext, Stage};
use crate::{Error, Result};

pub(crate) use crate::gpu::adapter::POSITION_FORMAT;

pub struct GBuffer {
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) position: wgpu::Texture,
    /// Geometric normal facing the camera (w = material): what every shadow test reads.
    pub(crate) normal: wgpu::Texture,
    /// Interpolated smooth normal: shading only.
    pub(crate) shading_normal: wgpu::Texture,
    pub(crate) position_view: wgpu::TextureView,
    pub(crate) normal_view: wgpu::TextureView,
    shading_normal_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
}

/// The G-buffer on the CPU: every later stage's CPU twin and the tests read this.
#[derive(Clone)]
pub struct GBufferCpu {
    pub width: u32,
    pub height: u32,
    /// xyz world position, w = 1 on geometry and 0 on background.
    pub position: Vec<[f32; 4]>,
    /// xyz geometric (flat) normal facing the camera, w = material index: shadow tests use it.
    pub normal: Vec<[f32; 4]>,
    /// xyz interpolated smooth normal, on the same side: shading uses it.
    pub shading_normal: Vec<[f32; 4]>,
}

impl GBufferCpu {
    pub fn is_geometry(&self, index: usize) -> bool {
        self.position[index][3] != 0.0
    }
    pub fn geometry_count(&self) -> usize {
        self.position.iter().filter(|p| p[3] != 0.0).count()
    }
}

pub struct GBufferPass {
    pipeline: wgpu::RenderPipeline,
}

impl GBufferPass {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        let module = pipeline::shader_module(ctx, Stage::GBUFFER.name)?;
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let target = Some(wgpu::ColorTargetState {
            format: POSITION_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        });
        let pipeline = ctx
            .device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(Stage::GBUFFER.name),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(vertex_layout(&VERTEX_ATTRIBUTES))],
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: wgpu::TextureFormat::Depth32Float,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Greater),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[target.clone(), target.clone(), target],
                }),
                multiview_mask: None,
                cache: None,
            });
        pipeline::check(scope, Stage::GBUFFER.name)?;
        Ok(Self { pipeline })
    }

    /// Allocates the G-buffer, checking the resolution against the device's limit.
    pub fn allocate(ctx: &GpuContext, width: u32, height: u32) -> Result<GBuffer> {
        let max = ctx.limits().max_texture_dimension_2d;
        if width > max || height > max {
            return Err(Error::Limit(format!(
                "resolution {width}x{height} exceeds this device's texture limit of {max}x{max} ({})",
                ctx.summary.name
            )));
        }
        let make = |label, format, usage| screen_texture(ctx, label, width, height, format, usage);
        let color = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let position = make("gbuffer position", POSITION_FORMAT, color);
        let normal = make("gbuffer normal", POSITION_FORMAT, color);
        let shading_normal = make("gbuffer shading normal", POSITION_FORMAT, color);
        let depth = make(
            "gbuffer depth",
            wgpu::TextureFormat::Depth32Float,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        Ok(GBuffer {
            width,
            height,
            position_view: position.create_view(&Default::default()),
            normal_view: normal.create_view(&Default::default()),
            shading_normal_view: shading_normal.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            position,
            normal,
            shading_normal,
        })
    }

    pub fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene: &SceneGpu,
        camera: &GpuCamera,
        g: &GBuffer,
    ) {
        let camera_buffer = readback::uniform_buffer(ctx, "camera", camera);
        let bind = pipeline::bind_group(
            ctx,
            &self.pipeline.get_bind_group_layout(0),
            bind::gbuffer::Pipeline {
                camera: camera_buffer.as_entire_binding(),
            },
        );
        let clear = wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            store: wgpu::StoreOp::Store,
        };
        let attachment = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: clear,
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(Stage::GBUFFER.name),
            color_attachments: &[
                attachment(&g.position_view),
                attachment(&g.normal_view),
                attachment(&g.shading_normal_view),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &g.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.set_vertex_buffer(0, scene.vertices.slice(..));
        pass.set_index_buffer(scene.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..scene.index_count, 0, 0..1);
    }
}

pub fn read_back(ctx: &GpuContext, g: &GBuffer) -> Result<GBufferCpu> {
    Ok(GBufferCpu {
        width: g.width,
        height: g.height,
        position: readback::read_texture(ctx, &g.position, 0, 16)?,
        normal: readback::read_texture(ctx, &g.normal, 0, 16)?,
        shading_normal: readback::read_texture(ctx, &g.shading_normal, 0, 16)?,
    })
}

/// The camera the G-buffer raster (and any pass that must match its pixels) draws with.
pub fn camera_uniform(scene: &crate::scene::Scene) -> GpuCamera {
    camera_uniform_for(scene, &scene.camera)
}

/// [`camera_uniform`] for another camera over the same meshes (a renderer whose camera moved).
pub(crate) fn camera_uniform_for(
    scene: &crate::scene::Scene,
    camera: &crate::scene::Camera,
) -> GpuCamera {
    let aspect = scene.render.width as f32 / scene.render.height as f32;
    GpuCamera {
        clip_from_world: camera
            .clip_from_world(aspect, &scene.bounds)
            .to_cols_array_2d(),
        eye: camera.eye.extend(1.0).to_array(),
    }
}

/// One screen-sized 2D texture (the G-buffer's attachments, and passes that must match its pixels).
pub(crate) fn screen_texture(
    ctx: &GpuContext,
    label: &str,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}
