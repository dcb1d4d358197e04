//! blur: separable box prefilter of the moment planes (horizontal into `scratch`, vertical back).

use crate::gpu::Stage;
use super::{groups, ComputeKernel, Dispatch, FrameGpu, PIXEL_WORKGROUP};
use crate::Result;

pub struct Blur {
    horizontal: ComputeKernel,
    vertical: ComputeKernel,
}

impl Blur {
    pub fn new(fg: &FrameGpu) -> Result<Self> {
        Ok(Self { horizontal: ComputeKernel::new(fg.ctx, Stage::BLUR, "horizontal")?, vertical: ComputeKernel::new(fg.ctx, Stage::BLUR, "vertical")? })
    }

    /// `source` → (horizontal) → `scratch` → (vertical) → `target`.
    pub fn record(
        &self,
        fg: &FrameGpu,
        enc: &mut wgpu::CommandEncoder,
        filter: &wgpu::Buffer,
        layers: u32,
        source: &wgpu::Buffer,
        scratch: &wgpu::Buffer,
        target: &wgpu::Buffer,
    ) {
        let size = fg.frame.map_size;
        let size3 = [groups(size, PIXEL_WORKGROUP[0]), groups(size, PIXEL_WORKGROUP[1]), layers];
        for (kernel, from, to) in [(&self.horizontal, source, scratch), (&self.vertical, scratch, target)] {
            kernel.dispatch(
                fg.ctx,
                enc,
                &[
                    ("frame", fg.frame_buffer.as_entire_binding()),
                    ("settings", filter.as_entire_binding()),
                    ("source", from.as_entire_binding()),
                    ("destination", to.as_entire_binding()),
                ],
                Dispatch::Direct(size3),
            );
        }
    }
}
