//! hybrid_build: merges full-resolution maps (layers of a transient raster) into a hybrid store,
//! the compact representation `kernels/shared/maps_hybrid.wgsl` reads (docs/hybrid.md).

use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP, PIXEL_WORKGROUP};
use crate::gpu::kernels::MapAccess;
use crate::gpu::stages::bind;
use crate::gpu::structs::{GpuHybridBuild, GpuHybridControl};
use crate::gpu::{readback, GpuContext, Stage};
use crate::render::shadow_raster::ShadowMapArray;
use crate::scene::HybridDef;
use crate::{Error, Result};

/// Pool texel (a % 4096, a / 4096) holds word a (`HYBRID_POOL_WIDTH_LOG2` in the kernels).
pub const POOL_WIDTH_LOG2: u32 = 12;
pub(crate) const POOL_WIDTH: u32 = 1 << POOL_WIDTH_LOG2;
/// A node with this bit points at 4 child nodes; without it, it is a depth's f32 bits.
pub const CHILDREN: u32 = 0x8000_0000;
/// One 16-bit depth unit in [0, 1] depth: `eps` is given in these (the seed's ε0 = 0.25).
pub const DEPTH_UNIT: f32 = 1.0 / 65535.0;
/// `GpuFrame.flags` bits 8..9 carry the levels to the lookup.
pub const FRAME_LEVELS_SHIFT: u32 = 8;

/// The four entry points of `kernels/hybrid_build.wgsl`.
pub(crate) struct HybridBuild {
    /// Nearest, clamped: textureGather returns the four texels exactly.
    sampler: wgpu::Sampler,
    classify: ComputeKernel,
    scan_rows: ComputeKernel,
    scan_total: ComputeKernel,
    emit: ComputeKernel,
}

/// The pool texture and the build's scratch buffers, sized once per scene and settings.
pub(crate) struct HybridStore {
    pub(crate) pool: wgpu::Texture,
    /// Sampled view, what map-reading kernels bind in place of a depth array.
    pub(crate) view: wgpu::TextureView,
    storage_view: wgpu::TextureView,
    pub(crate) control: wgpu::Buffer,
    offsets: wgpu::Buffer,
    row_starts: wgpu::Buffer,
    coarse_nodes: wgpu::Buffer,
    pub(crate) settings: HybridDef,
    pub(crate) coarse: u32,
    /// Root words at the start of the pool, one per slot.
    pub(crate) slots: u32,
    pub(crate) capacity_words: u32,
}

impl HybridBuild {
    /// `raster`: how the raster's layers are read (`Raster::raster_access`).
    pub(crate) fn new(ctx: &GpuContext, raster: MapAccess) -> Result<Self> {
        Ok(Self {
            sampler: ctx.device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("hybrid_build gather"),
                ..Default::default()
            }),
            classify: ComputeKernel::new_for(ctx, Stage::HYBRID_BUILD, "classify", raster)?,
            scan_rows: ComputeKernel::new(ctx, Stage::HYBRID_BUILD, "scan_rows")?,
            scan_total: ComputeKernel::new(ctx, Stage::HYBRID_BUILD, "scan_total")?,
            emit: ComputeKernel::new_for(ctx, Stage::HYBRID_BUILD, "emit", raster)?,
        })
    }

    /// Merges `raster` layer `layer` into `store` as slot `slot` (four dispatches, no wait).
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        store: &HybridStore,
        raster: &ShadowMapArray,
        layer: u32,
        slot: u32,
    ) {
        let s = store.settings;
        let uniform = GpuHybridBuild {
            levels: s.levels,
            coarse: store.coarse,
            layer,
            slot,
            capacity: store.capacity_words,
            eps: s.eps * DEPTH_UNIT,
            ..Default::default()
        };
        let build = readback::uniform_buffer(ctx, "hybrid_build", &uniform);
        let c = store.coarse;
        let grid = Dispatch::Direct([
            groups(c, PIXEL_WORKGROUP[0]),
            groups(c, PIXEL_WORKGROUP[1]),
            1,
        ]);
        let raster_view = wgpu::BindingResource::TextureView(&raster.array_view);
        self.classify.dispatch(
            ctx,
            enc,
            bind::hybrid_build::Classify {
                build: build.as_entire_binding(),
                raster: raster_view.clone(),
                offsets: store.offsets.as_entire_binding(),
                coarse_nodes: store.coarse_nodes.as_entire_binding(),
                gather_sampler: wgpu::BindingResource::Sampler(&self.sampler),
            },
            grid,
        );
        self.scan_rows.dispatch(
            ctx,
            enc,
            bind::hybrid_build::ScanRows {
                build: build.as_entire_binding(),
                offsets: store.offsets.as_entire_binding(),
                row_starts: store.row_starts.as_entire_binding(),
            },
            Dispatch::Direct([groups(c, LINE_WORKGROUP[0]), 1, 1]),
        );
        self.scan_total.dispatch(
            ctx,
            enc,
            bind::hybrid_build::ScanTotal {
                build: build.as_entire_binding(),
                row_starts: store.row_starts.as_entire_binding(),
                control: store.control.as_entire_binding(),
                pool: wgpu::BindingResource::TextureView(&store.storage_view),
            },
            Dispatch::Direct([1, 1, 1]),
        );
        let grid = Dispatch::Direct([
            groups(c, PIXEL_WORKGROUP[0]),
            groups(c, PIXEL_WORKGROUP[1]),
            1,
        ]);
        self.emit.dispatch(
            ctx,
            enc,
            bind::hybrid_build::Emit {
                build: build.as_entire_binding(),
                raster: raster_view,
                offsets: store.offsets.as_entire_binding(),
                row_starts: store.row_starts.as_entire_binding(),
                control: store.control.as_entire_binding(),
                pool: wgpu::BindingResource::TextureView(&store.storage_view),
                coarse_nodes: store.coarse_nodes.as_entire_binding(),
                gather_sampler: wgpu::BindingResource::Sampler(&self.sampler),
            },
            grid,
        );
    }
}

impl HybridStore {
    /// A store with `slots` roots and room for at least `capacity_bytes` (rounded up to whole pool
    /// rows, at most the device's texture height).
    pub(crate) fn new(
        ctx: &GpuContext,
        settings: HybridDef,
        slots: u32,
        capacity_bytes: u64,
    ) -> Result<Self> {
        let coarse = settings.base >> settings.levels;
        let max_rows = ctx.limits().max_texture_dimension_2d;
        let words = (capacity_bytes / 4).max(slots as u64 + coarse as u64 * coarse as u64);
        let rows = words.div_ceil(POOL_WIDTH as u64).min(max_rows as u64) as u32;
        let capacity_words = (rows as u64 * POOL_WIDTH as u64).min(u32::MAX as u64 / 2) as u32;
        if (capacity_words as u64) < slots as u64 + coarse as u64 * coarse as u64 {
            return Err(Error::Limit(format!(
                "hybrid maps: the store of {rows} x {POOL_WIDTH} words cannot hold one {coarse}x{coarse} coarse grid (base {}, levels {})",
                settings.base, settings.levels
            )));
        }
        let pool = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("hybrid store"),
            size: wgpu::Extent3d {
                width: POOL_WIDTH,
                height: rows,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Uint,
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = pool.create_view(&Default::default());
        let storage_view = pool.create_view(&Default::default());
        let control = readback::storage_buffer(
            ctx,
            "hybrid control",
            &[GpuHybridControl::default()],
            wgpu::BufferUsages::COPY_DST,
        );
        let offsets =
            readback::zeroed_storage(ctx, "hybrid offsets", coarse as u64 * coarse as u64 * 4);
        let row_starts = readback::zeroed_storage(ctx, "hybrid row starts", coarse as u64 * 4);
        let coarse_nodes = readback::zeroed_storage(
            ctx,
            "hybrid coarse nodes",
            coarse as u64 * coarse as u64 * 4,
        );
        let store = Self {
            pool,
            view,
            storage_view,
            control,
            offsets,
            row_starts,
            coarse_nodes,
            settings,
            coarse,
            slots,
            capacity_words,
        };
        store.reset(ctx);
        Ok(store)
    }

    /// Empties the store (its maps are no longer needed): allocation restarts after the roots.
    pub(crate) fn reset(&self, ctx: &GpuContext) {
        let empty = GpuHybridControl {
            used: self.slots,
            ..Default::default()
        };
        ctx.queue
            .write_buffer(&self.control, 0, bytemuck::bytes_of(&empty));
    }

    /// The allocation state (one read-back; submit the builds first).
    pub(crate) fn read_control(&self, ctx: &GpuContext) -> Result<GpuHybridControl> {
        Ok(readback::read_buffer::<GpuHybridControl>(ctx, &self.control, 16)?[0])
    }

    /// The first `words` words of the pool (tests and the twin comparison).
    pub(crate) fn read_words(&self, ctx: &GpuContext, words: u32) -> Result<Vec<u32>> {
        let all: Vec<u32> = readback::read_texture(ctx, &self.pool, 0, 4)?;
        Ok(all[..words as usize].to_vec())
    }

    pub(crate) fn capacity_bytes(&self) -> u64 {
        self.capacity_words as u64 * 4
    }

    /// The build's scratch buffers (offsets, row starts, coarse verdicts): reused by every map.
    pub(crate) fn scratch_bytes(&self) -> u64 {
        (2 * self.coarse as u64 * self.coarse as u64 + self.coarse as u64) * 4
    }
}
