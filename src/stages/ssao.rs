//! ssao: screen-space ambient occlusion from the G-buffer into an AO buffer (and occluded counts).

use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::Result;

pub(crate) struct Ssao {
    kernel: ComputeKernel,
}

impl Ssao {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: ComputeKernel::new(ctx, Stage::SSAO, "main")?,
        })
    }

    /// Writes `ao` and `occluded` at every pixel of a `size` (width, height) G-buffer, from the
    /// bindings the caller gives by name.
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        bindings: bind::ssao::Main,
        size: [u32; 2],
    ) {
        self.kernel.dispatch(
            ctx,
            enc,
            bindings,
            Dispatch::Direct([
                groups(size[0], PIXEL_WORKGROUP[0]),
                groups(size[1], PIXEL_WORKGROUP[1]),
                1,
            ]),
        );
    }
}

/// The fixed hemisphere kernel: `n` points, z ≥ 0.15 (off the tangent plane), lengths spread
/// towards the centre (scale 0.1..1), from a fixed generator.
pub(crate) fn hemisphere_kernel(n: u32) -> Vec<[f32; 4]> {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 40) as f32) / (1u64 << 24) as f32
    };
    (0..n)
        .map(|i| {
            let (a, z) = (next() * std::f32::consts::TAU, 0.15 + 0.85 * next());
            let r = (1.0 - z * z).sqrt();
            let f = (i as f32 + 0.5) / n as f32;
            let scale = 0.1 + 0.9 * f * f;
            [r * a.cos() * scale, r * a.sin() * scale, z * scale, 0.0]
        })
        .collect()
}
