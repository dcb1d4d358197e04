//! barycentrics: a second camera raster that writes, per pixel, the triangle it sees and the
//! pixel's barycentrics in it (for per-vertex methods). The G-buffer pass is untouched, so every
//! other method's inputs stay bit-identical; this pass runs only where a method asks for it.

use super::SceneGpu;
use crate::gpu::stages::bind;
use crate::gpu::structs::GpuCamera;
use crate::gpu::{pipeline, readback, GpuContext, Stage};
use crate::Result;

pub(crate) const IDS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

/// The pass's target: ids (triangle + 1, b1 bits, b2 bits, 0) and its own depth buffer.
pub(crate) struct TriangleIds {
    pub(crate) texture: wgpu::Texture,
    pub(crate) view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
}

pub(crate) struct BarycentricsPass {
    pipeline: wgpu::RenderPipeline,
}

impl BarycentricsPass {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self> {
        let module = pipeline::shader_module(ctx, Stage::BARYCENTRICS.name)?;
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipeline = ctx
            .device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(Stage::BARYCENTRICS.name),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                // As the G-buffer: no culling, reversed depth (Greater), so the same fragment wins every pixel.
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
                    targets: &[Some(wgpu::ColorTargetState {
                        format: IDS_FORMAT,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            });
        pipeline::check(scope, Stage::BARYCENTRICS.name)?;
        Ok(Self { pipeline })
    }

    pub(crate) fn allocate(ctx: &GpuContext, width: u32, height: u32) -> TriangleIds {
        let make = |label, format, usage| {
            super::gbuffer::screen_texture(ctx, label, width, height, format, usage)
        };
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let texture = make("triangle ids", IDS_FORMAT, usage);
        let depth = make(
            "triangle ids depth",
            wgpu::TextureFormat::Depth32Float,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        TriangleIds {
            view: texture.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            texture,
        }
    }

    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene: &SceneGpu,
        camera: &wgpu::Buffer,
        target: &TriangleIds,
    ) {
        let bindings = bind::barycentrics::Pipeline {
            camera: camera.as_entire_binding(),
            scene_vertices: scene.vertices.as_entire_binding(),
            scene_indices: scene.indices.as_entire_binding(),
        };
        let bind = pipeline::bind_group(ctx, &self.pipeline.get_bind_group_layout(0), bindings);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(Stage::BARYCENTRICS.name),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target.view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &target.depth_view,
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
        pass.draw(0..scene.index_count, 0..1);
    }
}

/// The ids texture on the CPU, one `[triangle + 1, b1 bits, b2 bits, 0]` per pixel.
pub(crate) fn read_back(ctx: &GpuContext, ids: &TriangleIds) -> Result<Vec<[u32; 4]>> {
    readback::read_texture(ctx, &ids.texture, 0, 16)
}

/// `camera`'s uniform buffer.
pub(crate) fn camera_buffer(ctx: &GpuContext, camera: &GpuCamera) -> wgpu::Buffer {
    readback::uniform_buffer(ctx, "barycentrics camera", camera)
}
