//! cull (scope = local): per new map, the triangles that can change a texel its pixels test,
//! compacted into an index list with draw_indexed_indirect arguments the GPU writes, so the
//! raster draws only those (docs/gpu-frame.md). A batch holds as many maps as whole-mesh index
//! slots fit one storage binding; batches reuse the slots within one submission.

use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP};
use crate::gpu::readback;
use crate::gpu::stages::bind;
use crate::gpu::structs::GpuCull;
use crate::gpu::{GpuContext, Stage};
use crate::render::SceneGpu;
use crate::scene::Scene;
use crate::Result;

/// u32 words of one slot's draw_indexed_indirect arguments.
pub const ARGS_WORDS: u32 = 5;
pub use crate::gpu::stages::CULL_RUN;
/// Index memory the slots may take together.
const SLOTS_BUDGET_BYTES: u64 = 256 << 20;

/// A batch of maps to cull for: their sample records and the culling tiles footprint wrote.
#[derive(Clone, Copy)]
pub struct CullBatch<'b> {
    pub samples: &'b wgpu::Buffer,
    pub tiles: &'b wgpu::Buffer,
}

pub struct Cull {
    runs_phase: ComputeKernel,
    begin: ComputeKernel,
    triangles: ComputeKernel,
    /// One slot of `stride` indices per map of a batch (INDEX | STORAGE).
    pub culled: wgpu::Buffer,
    /// ARGS_WORDS per slot (INDIRECT | STORAGE).
    pub args: wgpu::Buffer,
    /// The runs phase 1 passes (a word per run of every slot), its count and phase 2's dispatch.
    kept_runs: wgpu::Buffer,
    control: wgpu::Buffer,
    dispatch: wgpu::Buffer,
    /// GpuCull.cull_face: the face the shadow raster culls.
    cull_face: u32,
    /// Maps per batch.
    pub(crate) slots: u32,
    stride: u32,
}

impl Cull {
    /// None when the adapter cannot draw indirectly with a first instance, or when one whole-mesh
    /// slot does not fit a storage binding: maps are then rasterized whole. `scene_gpu` is
    /// `scene` uploaded (its shadow order gives the runs).
    pub fn new(
        ctx: &GpuContext,
        scene: &Scene,
        scene_gpu: &SceneGpu,
        max_maps: u32,
    ) -> Result<Option<Self>> {
        let stride = scene_gpu.index_count;
        let slot_bytes = stride as u64 * 4;
        let binding = ctx.limits().max_storage_buffer_binding_size;
        let slots =
            (binding.min(SLOTS_BUDGET_BYTES) / slot_bytes.max(4)).min(max_maps as u64) as u32;
        if slots == 0
            || !ctx
                .device
                .features()
                .contains(wgpu::Features::INDIRECT_FIRST_INSTANCE)
        {
            return Ok(None);
        }
        let storage =
            |label, bytes: u64, extra| readback::zeroed_storage_with(ctx, label, bytes, extra);
        let run_count = (stride / 3).div_ceil(CULL_RUN) as u64;
        Ok(Some(Self {
            kept_runs: storage(
                "cull kept runs",
                run_count * slots as u64 * 4,
                wgpu::BufferUsages::empty(),
            ),
            control: storage("cull control", 16, wgpu::BufferUsages::empty()),
            dispatch: storage("cull dispatch", 16, wgpu::BufferUsages::INDIRECT),
            cull_face: cull_face(scene.render.cull),
            runs_phase: ComputeKernel::new(ctx, Stage::CULL, "main")?,
            begin: ComputeKernel::new(ctx, Stage::CULL, "begin")?,
            triangles: ComputeKernel::new(ctx, Stage::CULL, "triangles")?,
            culled: storage(
                "culled indices",
                slot_bytes * slots as u64,
                wgpu::BufferUsages::INDEX,
            ),
            args: storage(
                "cull draw arguments",
                slots as u64 * ARGS_WORDS as u64 * 4,
                wgpu::BufferUsages::INDIRECT,
            ),
            slots,
            stride,
        }))
    }

    /// Culls for lattice samples `ks` (at most `slots`), slot n for ks[n]; `tiles` holds
    /// CULL_TILE_WORDS words per lattice sample; `frame` is the frame uniform and `scene_gpu` the
    /// scene `new` was built for (its shadow indices and vertices).
    pub fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        frame: &wgpu::Buffer,
        scene_gpu: &SceneGpu,
        batch: &CullBatch,
        ks: &[u32],
    ) {
        let CullBatch { samples, tiles } = *batch;
        assert!(
            ks.len() as u32 <= self.slots && !ks.is_empty(),
            "cull batch of {} maps, capacity {}",
            ks.len(),
            self.slots
        );
        let triangles = self.stride / 3;
        let total = groups(triangles.div_ceil(CULL_RUN), LINE_WORKGROUP[0]).max(1);
        let groups_x = total.min(ctx.limits().max_compute_workgroups_per_dimension);
        let uniform = GpuCull {
            triangle_count: triangles,
            slot_stride: self.stride,
            cull_face: self.cull_face,
            groups_x,
        };
        let uniform = readback::uniform_buffer(ctx, "cull", &uniform);
        let slots = readback::storage_buffer(ctx, "cull slots", ks, wgpu::BufferUsages::empty());
        enc.clear_buffer(&self.args, 0, None);
        enc.clear_buffer(&self.control, 0, None);
        self.runs_phase.dispatch(
            ctx,
            enc,
            bind::cull::Main {
                cull: uniform.as_entire_binding(),
                frame: frame.as_entire_binding(),
                samples: samples.as_entire_binding(),
                tiles: tiles.as_entire_binding(),
                runs: scene_gpu.runs.as_entire_binding(),
                slots: slots.as_entire_binding(),
                args: self.args.as_entire_binding(),
                kept_runs: self.kept_runs.as_entire_binding(),
                control: self.control.as_entire_binding(),
            },
            Dispatch::Direct([groups_x, ks.len() as u32, total.div_ceil(groups_x)]),
        );
        self.begin.dispatch(
            ctx,
            enc,
            bind::cull::Begin {
                control: self.control.as_entire_binding(),
                dispatch: self.dispatch.as_entire_binding(),
            },
            Dispatch::Direct([1, 1, 1]),
        );
        self.triangles.dispatch(
            ctx,
            enc,
            bind::cull::Triangles {
                cull: uniform.as_entire_binding(),
                frame: frame.as_entire_binding(),
                samples: samples.as_entire_binding(),
                tiles: tiles.as_entire_binding(),
                indices: scene_gpu.shadow_indices.as_entire_binding(),
                slots: slots.as_entire_binding(),
                culled: self.culled.as_entire_binding(),
                args: self.args.as_entire_binding(),
                positions: scene_gpu.positions.as_entire_binding(),
                kept_runs: self.kept_runs.as_entire_binding(),
                control: self.control.as_entire_binding(),
            },
            Dispatch::Indirect(&self.dispatch),
        );
    }

    /// Byte offset of slot n's draw arguments.
    pub(crate) fn args_offset(slot: u32) -> u64 {
        slot as u64 * ARGS_WORDS as u64 * 4
    }
}

/// GpuCull.cull_face for the shadow raster's cull mode.
pub fn cull_face(mode: crate::scene::CullMode) -> u32 {
    match mode {
        crate::scene::CullMode::None => 0,
        crate::scene::CullMode::Back => 1,
        crate::scene::CullMode::Front => 2,
    }
}
