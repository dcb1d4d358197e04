//! Read-backs: staging copy, map, wait. Texture rows are padded to 256 bytes and the padding stripped.

use super::GpuContext;
use crate::{Error, Result};
use bytemuck::Pod;
use wgpu::util::DeviceExt;

pub fn storage_buffer<T: Pod>(
    ctx: &GpuContext,
    label: &str,
    data: &[T],
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    ctx.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(data),
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST
                | extra,
        })
}

pub fn uniform_buffer<T: Pod>(ctx: &GpuContext, label: &str, data: &T) -> wgpu::Buffer {
    ctx.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::bytes_of(data),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        })
}

pub fn zeroed_storage(ctx: &GpuContext, label: &str, bytes: u64) -> wgpu::Buffer {
    zeroed_storage_with(ctx, label, bytes, wgpu::BufferUsages::empty())
}

/// As [`zeroed_storage`], with `extra` usages (`INDIRECT` for dispatch arguments).
pub(crate) fn zeroed_storage_with(
    ctx: &GpuContext,
    label: &str,
    bytes: u64,
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST
            | extra,
        mapped_at_creation: false,
    })
}

/// Copies `bytes` of `src` into a fresh staging buffer inside `encoder`; map it after submission.
pub(crate) fn stage_copy(
    ctx: &GpuContext,
    encoder: &mut wgpu::CommandEncoder,
    src: &wgpu::Buffer,
    bytes: u64,
) -> wgpu::Buffer {
    let staging = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: bytes.max(4),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    encoder.copy_buffer_to_buffer(src, 0, &staging, 0, bytes);
    staging
}

/// Maps a staging buffer after its copy was submitted; one CPU↔GPU synchronisation.
pub(crate) fn map_staging<T: Pod>(ctx: &GpuContext, staging: &wgpu::Buffer) -> Result<Vec<T>> {
    let slice = staging.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.wait()?;
    rx.recv()
        .map_err(|e| Error::Gpu(format!("map_async dropped: {e}")))?
        .map_err(|e| Error::Gpu(format!("map_async: {e}")))?;
    let data = {
        let view = slice
            .get_mapped_range()
            .map_err(|e| Error::Gpu(format!("mapped range: {e:?}")))?;
        bytemuck::pod_collect_to_vec(&view)
    };
    staging.unmap();
    Ok(data)
}

/// Reads a whole buffer back (submits its own copy).
pub fn read_buffer<T: Pod>(ctx: &GpuContext, src: &wgpu::Buffer, bytes: u64) -> Result<Vec<T>> {
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    let staging = stage_copy(ctx, &mut encoder, src, bytes);
    ctx.queue.submit([encoder.finish()]);
    map_staging(ctx, &staging)
}

/// Reads one layer of a texture with `texel_bytes` per texel, rows unpadded.
pub fn read_texture<T: Pod>(
    ctx: &GpuContext,
    texture: &wgpu::Texture,
    layer: u32,
    texel_bytes: u32,
) -> Result<Vec<T>> {
    let (w, h) = (texture.width(), texture.height());
    let row = w * texel_bytes;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let staging = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("texture readback"),
        size: (padded * h) as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d {
                x: 0,
                y: 0,
                z: layer,
            },
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    ctx.queue.submit([encoder.finish()]);
    let bytes: Vec<u8> = map_staging(ctx, &staging)?;
    let mut out = Vec::with_capacity((row * h) as usize);
    for y in 0..h as usize {
        let start = y * padded as usize;
        out.extend_from_slice(&bytes[start..start + row as usize]);
    }
    Ok(bytemuck::pod_collect_to_vec(&out))
}
