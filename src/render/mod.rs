//! Raster passes: scene upload, G-buffer, shadow-map raster.

pub(crate) mod barycentrics;
pub(crate) mod bvh;
pub(crate) mod gbuffer;
pub(crate) mod kept_maps;
pub(crate) mod redraw_cull;
pub(crate) mod shadow_order;
pub(crate) mod shadow_raster;

use crate::gpu::GpuContext;
use crate::scene::Scene;
use wgpu::util::DeviceExt;

/// The scene's geometry on the GPU.
pub struct SceneGpu {
    pub(crate) vertices: wgpu::Buffer,
    pub(crate) indices: wgpu::Buffer,
    /// The same triangles in the shadow raster's order (`shadow_order`): what shadow maps draw and
    /// the cull pass reads.
    pub(crate) shadow_indices: wgpu::Buffer,
    /// `shadow_indices` on the CPU (the cull pass's runs are built from it).
    pub shadow_order: Vec<u32>,
    /// Box and normal cone of each run of CULL_RUN triangles of the shadow order
    /// (`shadow_order::runs`): the cull pass and the compute raster drop runs facing away.
    pub(crate) runs: wgpu::Buffer,
    /// Vertex positions alone, a vec4 each: what the compute raster reads.
    pub(crate) positions: wgpu::Buffer,
    pub index_count: u32,
    /// Vertex positions and the box of each run of CULL_RUN triangles of the shadow order, on
    /// the CPU: what a kept map's redraw leaves out (`redraw_cull`).
    pub(crate) cpu_positions: Vec<glam::Vec3>,
    pub(crate) run_boxes: Vec<[glam::Vec3; 2]>,
}

impl SceneGpu {
    pub fn upload(ctx: &GpuContext, scene: &Scene) -> Self {
        let vertices = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("scene vertices"),
                contents: bytemuck::cast_slice(&scene.vertices),
                // STORAGE: the cull pass reads positions and triangles.
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
            });
        let indices = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("scene indices"),
                contents: bytemuck::cast_slice(&scene.indices),
                usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::STORAGE,
            });
        let positions: Vec<glam::Vec3> = scene
            .vertices
            .iter()
            .map(|v| glam::Vec3::from(v.position))
            .collect();
        let shadow_order = shadow_order::shadow_order(&positions, &scene.indices);
        let shadow_indices = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("scene shadow indices"),
                contents: bytemuck::cast_slice(&shadow_order),
                usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::STORAGE,
            });
        let runs = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("scene shadow runs"),
                contents: bytemuck::cast_slice(&shadow_order::runs(&positions, &shadow_order)),
                usage: wgpu::BufferUsages::STORAGE,
            });
        let padded: Vec<glam::Vec4> = positions.iter().map(|p| p.extend(1.0)).collect();
        let run_boxes = redraw_cull::run_boxes(
            &positions,
            &shadow_order,
            crate::gpu::stages::CULL_RUN as usize,
        );
        let cpu_positions = positions;
        let positions = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("scene positions"),
                contents: bytemuck::cast_slice(&padded),
                usage: wgpu::BufferUsages::STORAGE,
            });
        Self {
            vertices,
            indices,
            shadow_indices,
            shadow_order,
            runs,
            positions,
            index_count: scene.indices.len() as u32,
            cpu_positions,
            run_boxes,
        }
    }
}

/// Vertex layout of `scene::Vertex`: position, normal, material.
pub(crate) const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 3] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Uint32];

pub(crate) fn vertex_layout(attributes: &[wgpu::VertexAttribute]) -> wgpu::VertexBufferLayout<'_> {
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<crate::scene::Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes,
    }
}
