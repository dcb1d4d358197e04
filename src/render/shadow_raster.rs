//! shadow_raster: one depth-only raster per light sample into one layer of a `Depth32Float` array.
//! Arrays are sized by the layer limit and the memory budget; callers work chunk by chunk beyond it.

use super::{redraw_cull, SceneGpu, VERTEX_ATTRIBUTES};
use crate::gpu::stages::bind;
use crate::gpu::{pipeline, GpuContext, Stage};
use crate::scene::CullMode;
use crate::{Error, Result};
use wgpu::util::DeviceExt;

pub struct ShadowMapArray {
    /// `Depth32Float` (this raster's) or `R32Uint` depth bits (the compute raster's, copied in).
    pub texture: wgpu::Texture,
    pub array_view: wgpu::TextureView,
    pub(crate) layer_views: Vec<wgpu::TextureView>,
}

impl ShadowMapArray {
    pub(crate) fn layers(&self) -> u32 {
        self.layer_views.len() as u32
    }
}

/// How many maps one array may hold: the device's layer limit and the memory budget, whichever is less.
pub(crate) fn maps_per_array(ctx: &GpuContext, map_size: u32, budget_mib: u32) -> Result<u32> {
    let max_dim = ctx.limits().max_texture_dimension_2d;
    if map_size > max_dim {
        return Err(Error::Limit(format!(
            "shadow_map_size {map_size} exceeds this device's texture limit of {max_dim} ({})",
            ctx.summary.name
        )));
    }
    let map_bytes = map_size as u64 * map_size as u64 * 4;
    let budget = budget_mib as u64 * 1024 * 1024;
    let by_budget = budget / map_bytes;
    if by_budget == 0 {
        return Err(Error::Limit(format!(
            "one {map_size}x{map_size} shadow map ({} MiB) does not fit shadow_map_budget_mib = {budget_mib}",
            map_bytes.div_ceil(1024 * 1024)
        )));
    }
    Ok(by_budget.min(ctx.limits().max_texture_array_layers as u64) as u32)
}

pub fn allocate(ctx: &GpuContext, map_size: u32, layers: u32) -> ShadowMapArray {
    allocate_as(ctx, map_size, layers, false)
}

/// `words`: R32Uint layers the compute raster's depth bits are copied into, read through
/// kernels/shared/maps_words.wgsl; otherwise `Depth32Float` layers this raster renders.
pub fn allocate_as(ctx: &GpuContext, map_size: u32, layers: u32, words: bool) -> ShadowMapArray {
    // STORAGE_BINDING: under the GPU-steered loop a kernel stores maps into their layers.
    let (format, usage) = if words {
        (
            wgpu::TextureFormat::R32Uint,
            wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::STORAGE_BINDING,
        )
    } else {
        (
            wgpu::TextureFormat::Depth32Float,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        )
    };
    let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("shadow maps"),
        size: wgpu::Extent3d {
            width: map_size,
            height: map_size,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: usage | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let array_view = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let layer_views = (0..layers)
        .map(|l| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: l,
                array_layer_count: Some(1),
                ..Default::default()
            })
        })
        .collect();
    ShadowMapArray {
        texture,
        array_view,
        layer_views,
    }
}

/// Clears every layer to the far plane. wgpu would otherwise clear layers never rendered lazily, at
/// the first dispatch that binds the array, inside the timed frame.
pub fn clear_all(ctx: &GpuContext, array: &ShadowMapArray) -> Result<()> {
    if array.texture.format() == wgpu::TextureFormat::R32Uint {
        // The far value's bits (1.0), layer by layer: one layer of staging at a time.
        let size = array.texture.width();
        let far = vec![1.0f32.to_bits(); size as usize * size as usize];
        for layer in 0..array.layers() {
            ctx.queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &array.texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: layer,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(&far),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(size * 4),
                    rows_per_image: Some(size),
                },
                wgpu::Extent3d {
                    width: size,
                    height: size,
                    depth_or_array_layers: 1,
                },
            );
        }
        return ctx.wait();
    }
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    for view in &array.layer_views {
        enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow map clear"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
    }
    ctx.queue.submit([enc.finish()]);
    ctx.wait()
}

pub struct ShadowRasterPass {
    pipeline: wgpu::RenderPipeline,
    /// `vs_far`: the far plane over a scissor, depth test off (a kept map's rectangle cleared).
    far: wgpu::RenderPipeline,
}

impl ShadowRasterPass {
    pub fn new(ctx: &GpuContext, cull: CullMode) -> Result<Self> {
        let module = pipeline::shader_module(ctx, Stage::SHADOW_RASTER.name)?;
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let position_only = [VERTEX_ATTRIBUTES[0]];
        let pipeline = ctx
            .device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(Stage::SHADOW_RASTER.name),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(super::vertex_layout(&position_only))],
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: match cull {
                        CullMode::Back => Some(wgpu::Face::Back),
                        CullMode::Front => Some(wgpu::Face::Front),
                        CullMode::None => None,
                    },
                    ..Default::default()
                },
                // All bias is applied in the lookup (shared/common.wgsl), where the CPU twin can follow it.
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: wgpu::TextureFormat::Depth32Float,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: None,
                multiview_mask: None,
                cache: None,
            });
        pipeline::check(scope, Stage::SHADOW_RASTER.name)?;
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let far = ctx
            .device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("shadow_raster far"),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_far"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: wgpu::TextureFormat::Depth32Float,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Always),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: None,
                multiview_mask: None,
                cache: None,
            });
        pipeline::check(scope, Stage::SHADOW_RASTER.name)?;
        Ok(Self { pipeline, far })
    }

    /// Draws each job's scissor rectangle of its layer again and keeps the rest of the layer: the
    /// far plane over the rectangle, then the triangles that may cover it (`redraw_cull`, from
    /// the job's sample record in `records`). A texel's depth is the least over the triangles
    /// covering its centre, whatever else is drawn, so the rectangle ends as a fresh map's
    /// (docs/reuse.md).
    #[allow(clippy::too_many_arguments)] // one per input of the pass: the encoder, scene, samples on both sides, layers, jobs
    pub(crate) fn record_redraw(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene: &SceneGpu,
        samples: &wgpu::Buffer,
        records: &[crate::gpu::structs::GpuSample],
        array: &ShadowMapArray,
        jobs: &[RasterJob],
    ) {
        let bind = pipeline::bind_group(
            ctx,
            &self.pipeline.get_bind_group_layout(0),
            bind::shadow_raster::Pipeline {
                samples: samples.as_entire_binding(),
            },
        );
        let size = array.texture.width();
        // Every job's triangles, one after the other; `ranges[j]` is job j's.
        let mut lists: Vec<u32> = Vec::new();
        let mut ranges = Vec::with_capacity(jobs.len());
        for job in jobs {
            let start = lists.len() as u32;
            if let Some(rect) = job.scissor {
                let m =
                    glam::Mat4::from_cols_array_2d(&records[job.sample as usize].light_from_world);
                redraw_cull::triangles(
                    &redraw_cull::planes(m, size, rect),
                    &scene.cpu_positions,
                    &scene.shadow_order,
                    &scene.run_boxes,
                    crate::gpu::stages::CULL_RUN as usize,
                    &mut lists,
                );
            }
            ranges.push(start..lists.len() as u32);
        }
        // An index buffer cannot be empty: one unused index keeps it valid.
        if lists.is_empty() {
            lists.push(0);
        }
        let indices = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("shadow_raster redraw indices"),
                contents: bytemuck::cast_slice(&lists),
                usage: wgpu::BufferUsages::INDEX,
            });
        for (job, range) in jobs.iter().zip(ranges) {
            let Some([x, y, w, h]) = job.scissor else {
                continue;
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(Stage::SHADOW_RASTER.name),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &array.layer_views[job.layer as usize],
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_scissor_rect(x, y, w, h);
            pass.set_pipeline(&self.far);
            pass.draw(0..3, 0..1);
            if range.is_empty() {
                continue;
            }
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.set_vertex_buffer(0, scene.vertices.slice(..));
            pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(range, 0, job.sample..job.sample + 1);
        }
    }

    /// Records one render pass per `(sample index, layer)`; `scissor` limits a map to a texel rectangle.
    pub fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene: &SceneGpu,
        samples: &wgpu::Buffer,
        array: &ShadowMapArray,
        jobs: &[RasterJob],
    ) {
        let bind = pipeline::bind_group(
            ctx,
            &self.pipeline.get_bind_group_layout(0),
            bind::shadow_raster::Pipeline {
                samples: samples.as_entire_binding(),
            },
        );
        for job in jobs {
            let mut pass = self.begin_layer(encoder, array, job, &bind, scene);
            pass.set_index_buffer(scene.shadow_indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..scene.index_count, 0, job.sample..job.sample + 1);
        }
    }
}

impl ShadowRasterPass {
    /// One layer's pass, cleared, with the pipeline, samples, scissor and vertices set: what
    /// `record` and `record_culled` share before their draws.
    fn begin_layer<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        array: &ShadowMapArray,
        job: &RasterJob,
        bind: &wgpu::BindGroup,
        scene: &SceneGpu,
    ) -> wgpu::RenderPass<'e> {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(Stage::SHADOW_RASTER.name),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &array.layer_views[job.layer as usize],
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind, &[]);
        if let Some([x, y, w, h]) = job.scissor {
            pass.set_scissor_rect(x, y, w, h);
        }
        pass.set_vertex_buffer(0, scene.vertices.slice(..));
        pass
    }
}

impl ShadowRasterPass {
    /// Like `record`, but each job draws the triangles the cull pass kept: indices and draw
    /// arguments (count, first index, the sample as first instance) come from the GPU, the
    /// arguments at the byte offset given with each job.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record_culled(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene: &SceneGpu,
        samples: &wgpu::Buffer,
        array: &ShadowMapArray,
        jobs: &[(RasterJob, u64)],
        culled: &wgpu::Buffer,
        args: &wgpu::Buffer,
    ) {
        let bind = pipeline::bind_group(
            ctx,
            &self.pipeline.get_bind_group_layout(0),
            bind::shadow_raster::Pipeline {
                samples: samples.as_entire_binding(),
            },
        );
        for (job, offset) in jobs {
            let mut pass = self.begin_layer(encoder, array, job, &bind, scene);
            pass.set_index_buffer(culled.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed_indirect(args, *offset);
        }
    }
}

/// One shadow map to rasterize: which sample (index into the samples buffer) into which layer.
#[derive(Clone, Copy, Debug)]
pub struct RasterJob {
    pub sample: u32,
    pub layer: u32,
    pub scissor: Option<[u32; 4]>,
}
