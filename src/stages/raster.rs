//! The frame's shadow-map raster, by the `raster` setting: the fixed-function `shadow_raster`, or
//! the `raster_compute` kernels whose maps are copied, chain by chain, into R32Uint layers that every
//! map-reading kernel reads through kernels/shared/maps_words.wgsl. Methods ask this for their map
//! arrays, so the layers' format always matches the raster that fills them, and for the stage
//! they time its work as (`Raster::stage`), so each raster has its own timing key.

use super::raster_compute::{RasterCompute, Requests};
use crate::gpu::kernels::MapAccess;
use crate::gpu::structs::GpuRasterJob;
use crate::gpu::{GpuContext, Stage};
use crate::render::shadow_raster::{self, RasterJob, ShadowMapArray, ShadowRasterPass};
use crate::render::SceneGpu;
use crate::scene::{CullMode, MapKind};
use crate::{Error, Result};
use std::cell::RefCell;

/// Maps one compute chain holds at most: enough (triangle, map) pairs to fill a large GPU, and a
/// small share of the map budget.
pub(crate) const CHAIN_MAPS: u32 = 32;

/// What a raster call draws: the scene, the sample records whose view-projections its jobs name,
/// and the array whose layers the maps go into.
#[derive(Clone, Copy)]
pub(crate) struct RasterTarget<'b> {
    pub(crate) scene: &'b SceneGpu,
    pub(crate) samples: &'b wgpu::Buffer,
    pub(crate) array: &'b ShadowMapArray,
}

pub enum Raster {
    Hardware(ShadowRasterPass),
    Compute(ComputeRaster),
}

/// The compute raster: a chain per map size in use (a hybrid method rasterizes at `hybrid.base`).
pub struct ComputeRaster {
    cull: CullMode,
    budget_mib: u32,
    chains: RefCell<Vec<RasterCompute>>,
}

impl Raster {
    /// `budget_mib`: the scene's `shadow_map_budget_mib`, which a compute chain takes its share of.
    pub fn new(ctx: &GpuContext, cull: CullMode, compute: bool, budget_mib: u32) -> Result<Self> {
        Ok(if compute {
            Raster::Compute(ComputeRaster {
                cull,
                budget_mib,
                chains: RefCell::new(Vec::new()),
            })
        } else {
            Raster::Hardware(ShadowRasterPass::new(ctx, cull)?)
        })
    }

    pub(crate) fn is_compute(&self) -> bool {
        matches!(self, Raster::Compute(_))
    }

    /// The stage its work is timed as, and named in `stages_ms`: `shadow_raster` (the
    /// fixed-function pipeline) or `raster_compute` (its kernels and copies into the layers).
    pub(crate) fn stage(&self) -> Stage {
        match self {
            Raster::Hardware(_) => Stage::SHADOW_RASTER,
            Raster::Compute(_) => Stage::RASTER_COMPUTE,
        }
    }

    /// `hardware` or `compute`, as run.json and the report name it.
    pub(crate) fn name(&self) -> &'static str {
        if self.is_compute() {
            "compute"
        } else {
            "hardware"
        }
    }

    /// How map-reading kernels read maps of representation `maps` filled by this raster.
    pub(crate) fn access(&self, maps: MapKind) -> MapAccess {
        MapAccess::of(maps, self.is_compute())
    }

    /// How kernels read this raster's own layers (moments, hybrid_build).
    pub(crate) fn raster_access(&self) -> MapAccess {
        MapAccess::raster_of(self.is_compute())
    }

    /// Maps one array may hold. The compute raster's chain takes its share of the budget first.
    pub fn maps_per_array(&self, ctx: &GpuContext, map_size: u32, budget_mib: u32) -> Result<u32> {
        let all = shadow_raster::maps_per_array(ctx, map_size, budget_mib)?;
        if !self.is_compute() {
            return Ok(all);
        }
        let chain = chain_maps(ctx, map_size, budget_mib)?;
        let budget_maps =
            (budget_mib as u64 * 1024 * 1024) / (map_size as u64 * map_size as u64 * 4);
        let left = budget_maps.saturating_sub(chain as u64).min(all as u64) as u32;
        if left == 0 {
            return Err(Error::Limit(format!(
                "raster = compute needs two {map_size}x{map_size} maps (one rasterized, one read) and shadow_map_budget_mib = {budget_mib} holds one; raise the budget or use raster = hardware"
            )));
        }
        Ok(left)
    }

    /// An array of `layers` maps in the format this raster fills.
    pub(crate) fn allocate(&self, ctx: &GpuContext, map_size: u32, layers: u32) -> ShadowMapArray {
        shadow_raster::allocate_as(ctx, map_size, layers, self.is_compute())
    }

    /// Rasterizes `jobs` (sample → layer, optionally inside a scissor rectangle) into `array`.
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        to: &RasterTarget,
        jobs: &[RasterJob],
    ) -> Result<()> {
        let RasterTarget {
            scene,
            samples,
            array,
        } = *to;
        match self {
            Raster::Hardware(pass) => {
                pass.record(ctx, enc, scene, samples, array, jobs);
                Ok(())
            }
            Raster::Compute(c) => c.record(ctx, enc, to, jobs),
        }
    }

    /// Draws each job's scissor rectangle of its layer again and keeps the rest of the layer (a
    /// kept map a moved mesh touched, docs/reuse.md); a job without a rectangle draws nothing.
    /// `records` are the sample records on the CPU (`job.sample` indexes them): the hardware
    /// raster draws only the triangles that may cover a job's rectangle (`redraw_cull`).
    pub(crate) fn record_redraw(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        to: &RasterTarget,
        records: &[crate::gpu::structs::GpuSample],
        jobs: &[RasterJob],
    ) -> Result<()> {
        let RasterTarget {
            scene,
            samples,
            array,
        } = *to;
        match self {
            Raster::Hardware(pass) => {
                pass.record_redraw(ctx, enc, scene, samples, records, array, jobs);
                Ok(())
            }
            Raster::Compute(c) => c.record_redraw(ctx, enc, to, jobs),
        }
    }

    /// Each job draws the triangles the cull pass kept for it: its slot's index list, whose draw
    /// arguments (index count first) sit at the byte offset given with the job, in `args`.
    pub(crate) fn record_culled(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        to: &RasterTarget,
        jobs: &[(RasterJob, u64)],
        culled: &wgpu::Buffer,
        args: &wgpu::Buffer,
    ) -> Result<()> {
        let RasterTarget {
            scene,
            samples,
            array,
        } = *to;
        match self {
            Raster::Hardware(pass) => {
                pass.record_culled(ctx, enc, scene, samples, array, jobs, culled, args);
                Ok(())
            }
            Raster::Compute(c) => {
                let slot_bytes = crate::stages::cull::ARGS_WORDS as u64 * 4;
                let kept: Vec<(RasterJob, u32)> = jobs
                    .iter()
                    .map(|(j, at)| (*j, (at / slot_bytes) as u32))
                    .collect();
                c.record_jobs(ctx, enc, to, &kept, Some((culled, args)))
            }
        }
    }

    /// The GPU-steered loop's draws over the whole mesh, each job's instance count a request flag
    /// the GPU set (`args` at the job's offset). The compute raster rasterizes every job instead
    /// (its own steered path is `record_requested`).
    pub(crate) fn record_flagged(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        to: &RasterTarget,
        jobs: &[(RasterJob, u64)],
        args: &wgpu::Buffer,
    ) -> Result<()> {
        let RasterTarget {
            scene,
            samples,
            array,
        } = *to;
        match self {
            Raster::Hardware(pass) => {
                pass.record_culled(
                    ctx,
                    enc,
                    scene,
                    samples,
                    array,
                    jobs,
                    &scene.shadow_indices,
                    args,
                );
                Ok(())
            }
            Raster::Compute(c) => {
                let plain: Vec<RasterJob> = jobs.iter().map(|(j, _)| *j).collect();
                c.record(ctx, enc, to, &plain)
            }
        }
    }
}

impl Raster {
    /// Under the GPU-steered loop: rasterizes only the maps a level's request list names (among
    /// `candidates` possible), into the layers their sample records name, with dispatches the GPU
    /// sizes from the list's count. The compute raster alone can: the fixed-function one draws
    /// every candidate layer (`record_culled` with GPU instance counts).
    pub(crate) fn record_requested(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        to: &RasterTarget,
        requests: (&wgpu::Buffer, &wgpu::Buffer),
        candidates: u32,
    ) -> Result<()> {
        let RasterTarget {
            scene,
            samples,
            array,
        } = *to;
        let Raster::Compute(c) = self else {
            return Err(Error::Param(
                "record_requested needs raster = compute".into(),
            ));
        };
        let size = array.texture.width();
        let chains = c.chain(ctx, size, scene.index_count / 3)?;
        let chain = chains
            .iter()
            .find(|r| r.map_size == size)
            .expect("a chain of this size");
        // As many chains as the candidates could fill; those past the level's count do nothing.
        for first in (0..candidates).step_by(chain.capacity as usize) {
            let requests = Requests {
                control: requests.0,
                list: requests.1,
                first,
            };
            chain.record_requested(ctx, enc, scene, samples, &requests, &array.array_view);
        }
        Ok(())
    }
}

/// Maps per compute chain: CHAIN_MAPS, or fewer where a quarter of the budget or the device allows fewer.
pub fn chain_maps(ctx: &GpuContext, map_size: u32, budget_mib: u32) -> Result<u32> {
    let map_bytes = map_size as u64 * map_size as u64 * 4;
    let quarter = ((budget_mib as u64 * 1024 * 1024) / 4 / map_bytes).max(1) as u32;
    Ok(
        super::raster_compute::maps_per_chain(ctx, map_size, budget_mib)?
            .min(quarter)
            .min(CHAIN_MAPS),
    )
}

impl ComputeRaster {
    /// The chains, with one of `size` built if there was none; its large-pair queue is sized for a
    /// mesh of `triangles` (a chain built for a smaller mesh is built again).
    fn chain(
        &self,
        ctx: &GpuContext,
        size: u32,
        triangles: u32,
    ) -> Result<std::cell::RefMut<'_, Vec<RasterCompute>>> {
        let mut chains = self.chains.borrow_mut();
        if !chains
            .iter()
            .any(|c| c.map_size == size && c.triangles >= triangles)
        {
            chains.retain(|c| c.map_size != size);
            // The share `maps_per_array` left out of the method's arrays.
            let maps = chain_maps(ctx, size, self.budget_mib)?;
            chains.push(RasterCompute::for_mesh(
                ctx,
                size,
                self.cull,
                maps,
                self.budget_mib,
                triangles,
            )?);
        }
        Ok(chains)
    }

    fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        to: &RasterTarget,
        jobs: &[RasterJob],
    ) -> Result<()> {
        let whole: Vec<(RasterJob, u32)> = jobs
            .iter()
            .map(|j| (*j, GpuRasterJob::WHOLE_MESH))
            .collect();
        self.record_jobs(ctx, enc, to, &whole, None)
    }

    /// The chain rasterizes each job inside its rectangle (far outside it), and only the
    /// rectangle is copied into the layer.
    fn record_redraw(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        to: &RasterTarget,
        jobs: &[RasterJob],
    ) -> Result<()> {
        let RasterTarget { scene, samples, .. } = *to;
        let size = to.array.texture.width();
        let chains = self.chain(ctx, size, scene.index_count / 3)?;
        let chain = chains
            .iter()
            .find(|c| c.map_size == size)
            .expect("a chain of this size");
        let jobs: Vec<&RasterJob> = jobs.iter().filter(|j| j.scissor.is_some()).collect();
        for part in jobs.chunks(chain.capacity as usize) {
            let words: Vec<GpuRasterJob> = part
                .iter()
                .map(|j| GpuRasterJob {
                    kept_slot: GpuRasterJob::WHOLE_MESH,
                    ..GpuRasterJob::new(j.sample, size, j.scissor)
                })
                .collect();
            chain.record_kept(ctx, enc, scene, samples, &words, None);
            for (m, job) in part.iter().enumerate() {
                chain.copy_rect(
                    enc,
                    m as u32,
                    &to.array.texture,
                    job.layer,
                    job.scissor.expect("filtered above"),
                );
            }
        }
        Ok(())
    }

    /// Chain by chain: rasterize, then copy each map into its layer. A job's second field is its
    /// cull slot (`kept` holds the pass's lists and arguments) or GpuRasterJob::WHOLE_MESH.
    fn record_jobs(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        to: &RasterTarget,
        jobs: &[(RasterJob, u32)],
        kept: Option<(&wgpu::Buffer, &wgpu::Buffer)>,
    ) -> Result<()> {
        let RasterTarget {
            scene,
            samples,
            array,
        } = *to;
        let size = array.texture.width();
        let chains = self.chain(ctx, size, scene.index_count / 3)?;
        let chain = chains
            .iter()
            .find(|c| c.map_size == size)
            .expect("a chain of this size");
        for part in jobs.chunks(chain.capacity as usize) {
            let words: Vec<GpuRasterJob> = part
                .iter()
                .map(|(j, slot)| GpuRasterJob {
                    kept_slot: *slot,
                    ..GpuRasterJob::new(j.sample, size, j.scissor)
                })
                .collect();
            chain.record_kept(ctx, enc, scene, samples, &words, kept);
            for (m, (job, _)) in part.iter().enumerate() {
                chain.copy_map(enc, m as u32, &array.texture, job.layer);
            }
        }
        Ok(())
    }
}
