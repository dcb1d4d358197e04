//! shadow_test: caches lit_k(p) of newly rendered maps as bits of each pixel's lattice mask; under
//! scope = local only for the (pixel, sample) pairs the level's items and probes consult, once each.

use super::buffers::AdaptiveBuffers;
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use super::FrameGpu;
use crate::gpu::{readback, GpuContext};
use crate::layout::{GpuLevel, GpuTestList};
use crate::scene::MapKind;
use crate::Result;

pub struct ShadowTest {
    /// scope = global: `gather` (the requested samples into `list`), then `main`.
    gather: ComputeKernel,
    kernel: ComputeKernel,
    /// The requested samples of the test list (uniform in `main`, written by `gather`).
    pub list: wgpu::Buffer,
    /// scope = local: `list` (items) and `probes`.
    local: Option<[ComputeKernel; 2]>,
}

impl ShadowTest {
    /// `maps`: the representation `main` reads; `local`: also the entry points of scope = local
    /// (which reads plain depth arrays).
    pub fn new(ctx: &GpuContext, maps: MapKind, local: bool) -> Result<Self> {
        let local = if local {
            Some([ComputeKernel::new(ctx, "shadow_test", "list")?, ComputeKernel::new(ctx, "shadow_test", "probes")?])
        } else {
            None
        };
        let size = std::mem::size_of::<GpuTestList>() as u64;
        let limit = ctx.limits().max_uniform_buffer_binding_size as u64;
        if size > limit {
            return Err(crate::Error::Gpu(format!("shadow_test's uniform list needs {size} bytes, the adapter binds at most {limit}")));
        }
        let list = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("shadow_test list"),
            size,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Ok(Self {
            gather: ComputeKernel::new(ctx, "shadow_test", "gather")?,
            kernel: ComputeKernel::new_for(ctx, "shadow_test", "main", maps)?,
            list,
            local,
        })
    }

    /// scope = local: tests the four corners of each of this level's items (`items`, counted by
    /// `b.item_total`) that no earlier item or probe of the frame tested for that pixel.
    pub fn record_list(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, quads: &wgpu::Buffer, items: &wgpu::Buffer, maps: [&wgpu::TextureView; 2]) {
        let kernels = self.local.as_ref().expect("ShadowTest built for scope = local");
        self.dispatch_local(fg, enc, b, &kernels[0], quads, items, &b.item_total, &b.list_args, maps);
    }

    /// scope = local: tests the five new samples of each of this level's probes (`b.probes`,
    /// counted by `b.probe_total`; `quads` holds the probed parents' children), once per pixel.
    pub fn record_probes(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, quads: &wgpu::Buffer, maps: [&wgpu::TextureView; 2]) {
        let kernels = self.local.as_ref().expect("ShadowTest built for scope = local");
        self.dispatch_local(fg, enc, b, &kernels[1], quads, &b.probes, &b.probe_total, &b.probe_args, maps);
    }

    #[allow(clippy::too_many_arguments)]
    fn dispatch_local(
        &self,
        fg: &FrameGpu,
        enc: &mut wgpu::CommandEncoder,
        b: &AdaptiveBuffers,
        kernel: &ComputeKernel,
        quads: &wgpu::Buffer,
        work: &wgpu::Buffer,
        total: &wgpu::Buffer,
        args: &wgpu::Buffer,
        maps: [&wgpu::TextureView; 2],
    ) {
        kernel.dispatch(
            fg.ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (2, b.samples.as_entire_binding()),
                (4, wgpu::BindingResource::TextureView(&fg.gbuffer.position_view)),
                (5, wgpu::BindingResource::TextureView(&fg.gbuffer.normal_view)),
                (10, b.consulted.as_entire_binding()),
                (11, b.masks.as_entire_binding()),
                (12, wgpu::BindingResource::TextureView(maps[0])),
                (13, wgpu::BindingResource::TextureView(maps[1])),
                (14, work.as_entire_binding()),
                (15, total.as_entire_binding()),
                (16, quads.as_entire_binding()),
                (17, b.control.as_entire_binding()),
            ],
            Dispatch::Indirect(args),
        );
    }

    /// Tests lattice samples `ks` (ascending), whose maps are layers of `maps` (or slots of a
    /// hybrid store's view); skips those not requested this frame.
    pub fn record(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, maps: &wgpu::TextureView, ks: &[u32]) {
        let ctx = fg.ctx;
        let level = readback::uniform_buffer(ctx, "level", &GpuLevel { work_count: ks.len() as u32, ..Default::default() });
        let list = readback::storage_buffer(ctx, "test list", ks, wgpu::BufferUsages::empty());
        self.dispatch(fg, enc, b, maps, &level, &list);
    }

    /// Tests the samples the last subdivide requested (`b.new_samples`, as many as it appended):
    /// the GPU-steered loop, when a level's maps fit one array.
    pub fn record_requested(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, maps: &wgpu::TextureView) {
        let level = readback::uniform_buffer(fg.ctx, "level", &GpuLevel { requested: 1, ..Default::default() });
        self.dispatch(fg, enc, b, maps, &level, &b.new_samples);
    }

    /// `gather`: the requested samples of `list` (its length or count as `level` says) into `self.list`.
    #[allow(clippy::too_many_arguments)]
    pub fn record_gather(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        level: &wgpu::Buffer,
        samples: &wgpu::Buffer,
        list: &wgpu::Buffer,
        lattice_state: &wgpu::Buffer,
        control: &wgpu::Buffer,
    ) {
        self.gather.dispatch(
            ctx,
            enc,
            &[
                (1, level.as_entire_binding()),
                (2, samples.as_entire_binding()),
                (3, list.as_entire_binding()),
                (8, lattice_state.as_entire_binding()),
                (9, control.as_entire_binding()),
                (19, self.list.as_entire_binding()),
            ],
            Dispatch::Direct([1, 1, 1]),
        );
    }

    fn dispatch(&self, fg: &FrameGpu, enc: &mut wgpu::CommandEncoder, b: &AdaptiveBuffers, maps: &wgpu::TextureView, level: &wgpu::Buffer, list: &wgpu::Buffer) {
        let ctx = fg.ctx;
        self.record_gather(ctx, enc, level, &b.samples, list, &b.lattice_state, &b.control);
        self.kernel.dispatch(
            ctx,
            enc,
            &[
                (0, fg.frame_buffer.as_entire_binding()),
                (4, wgpu::BindingResource::TextureView(&fg.gbuffer.position_view)),
                (5, wgpu::BindingResource::TextureView(&fg.gbuffer.normal_view)),
                (6, wgpu::BindingResource::TextureView(maps)),
                (7, b.masks.as_entire_binding()),
                (18, self.list.as_entire_binding()),
            ],
            Dispatch::Direct([groups(b.width, PIXEL_WORKGROUP[0]), groups(b.height, PIXEL_WORKGROUP[1]), 1]),
        );
    }
}
