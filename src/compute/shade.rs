//! shade: accumulates weight_i · lit_i(p) over one array's samples into the visibility buffer.

use super::groups;
use crate::gpu::{pipeline, readback, GpuContext};
use crate::layout::{GpuSample, GpuShadeChunk};
use crate::render::gbuffer::GBuffer;
use crate::Result;

pub const WORKGROUP: [u32; 3] = super::PIXEL_WORKGROUP;
/// Samples per `main` dispatch (`SHADE_BLOCK` in kernels/shade.wgsl, which unrolls them).
pub const SHADE_BLOCK: u32 = 16;

pub struct ShadePass {
    pipeline: wgpu::ComputePipeline,
    from_masks: super::ComputeKernel,
}

/// Buffers and views every shade call reads.
pub struct ShadeInputs<'a> {
    pub frame: &'a wgpu::Buffer,
    pub samples: &'a wgpu::Buffer,
    pub weights: &'a wgpu::Buffer,
    pub gbuffer: &'a GBuffer,
    pub visibility: &'a wgpu::Buffer,
}

impl ShadePass {
    /// `maps`: the representation `main` reads (from_masks reads no maps).
    pub fn new(ctx: &GpuContext, maps: crate::scene::MapKind) -> Result<Self> {
        Ok(Self {
            pipeline: pipeline::compute_pipeline_for(ctx, "shade", "main", maps)?,
            from_masks: super::ComputeKernel::new(ctx, "shade", "from_masks")?,
        })
    }

    /// Adds samples `first .. first + count` (all in `maps`: a depth array, or a hybrid store's view)
    /// to the visibility buffer.
    pub fn record(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &ShadeInputs,
        maps: &wgpu::TextureView,
        first: u32,
        count: u32,
    ) {
        let sample_bytes = std::mem::size_of::<GpuSample>() as u64;
        // Blocks in order, each adding to V in sample order: the sum order is the single loop's.
        for block in (first..first + count).step_by(SHADE_BLOCK as usize) {
            let block_count = SHADE_BLOCK.min(first + count - block);
            let chunk = readback::uniform_buffer(ctx, "shade chunk", &GpuShadeChunk { first_sample: block, sample_count: block_count, pad0: 0, pad1: 0 });
            // The block's samples and weights as uniforms (see kernels/shade.wgsl); a short last
            // block leaves the tail zero, and the kernel adds nothing for it.
            let block_samples = block_uniform(ctx, "shade block samples", SHADE_BLOCK as u64 * sample_bytes);
            let block_weights = block_uniform(ctx, "shade block weights", SHADE_BLOCK as u64 * 4);
            encoder.copy_buffer_to_buffer(inputs.samples, block as u64 * sample_bytes, &block_samples, 0, block_count as u64 * sample_bytes);
            encoder.copy_buffer_to_buffer(inputs.weights, block as u64 * 4, &block_weights, 0, block_count as u64 * 4);
            let bind = pipeline::bind_group(
                ctx,
                "shade",
                &self.pipeline.get_bind_group_layout(0),
                &[
                    inputs.frame.as_entire_binding(),
                    chunk.as_entire_binding(),
                    block_samples.as_entire_binding(),
                    block_weights.as_entire_binding(),
                    wgpu::BindingResource::TextureView(&inputs.gbuffer.position_view),
                    wgpu::BindingResource::TextureView(&inputs.gbuffer.normal_view),
                    wgpu::BindingResource::TextureView(maps),
                    inputs.visibility.as_entire_binding(),
                ],
            );
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("shade"), timestamp_writes: None });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(groups(inputs.gbuffer.width, WORKGROUP[0]), groups(inputs.gbuffer.height, WORKGROUP[1]), 1);
        }
    }

    /// Adaptive, scope = global: V = Σ_k ŵ_k · bit_k(p) from the cached lattice masks.
    #[allow(clippy::too_many_arguments)]
    pub fn record_masks(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::Buffer,
        weights: &wgpu::Buffer,
        gbuffer: &GBuffer,
        masks: &wgpu::Buffer,
        visibility: &wgpu::Buffer,
    ) {
        self.from_masks.dispatch(
            ctx,
            encoder,
            &[
                (0, frame.as_entire_binding()),
                (9, weights.as_entire_binding()),
                (4, wgpu::BindingResource::TextureView(&gbuffer.position_view)),
                (7, visibility.as_entire_binding()),
                (8, masks.as_entire_binding()),
            ],
            super::Dispatch::Direct([groups(gbuffer.width, WORKGROUP[0]), groups(gbuffer.height, WORKGROUP[1]), 1]),
        );
    }
}

/// A zeroed uniform buffer that a block's copy fills.
fn block_uniform(ctx: &GpuContext, label: &str, bytes: u64) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
