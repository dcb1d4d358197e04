//! moments: the centre map's depths as the statistic a filtered method prefilters.

use crate::gpu::Stage;
use super::{groups, ComputeKernel, Dispatch, FrameGpu, PIXEL_WORKGROUP};
use crate::Result;

pub struct Moments {
    kernel: ComputeKernel,
}

impl Moments {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { kernel: ComputeKernel::new(fg.ctx, Stage::MOMENTS, "main")? })
    }

    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, filter: &wgpu::Buffer, samples: &wgpu::Buffer, maps: &wgpu::TextureView, out: &wgpu::Buffer) {
        let size = fg.frame.map_size;
        self.kernel.dispatch(
            fg.ctx,
            enc,
            &[
                ("frame", fg.frame_buffer.as_entire_binding()),
                ("settings", filter.as_entire_binding()),
                ("samples", samples.as_entire_binding()),
                ("shadow_maps", wgpu::BindingResource::TextureView(maps)),
                ("moments", out.as_entire_binding()),
            ],
            Dispatch::Direct([groups(size, PIXEL_WORKGROUP[0]), groups(size, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
