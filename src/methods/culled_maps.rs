//! `cull = on` where a list of tiles tests every map (the regular grid and scope = global: the
//! frame's geometry tiles; a `regions` group: its own): a batch's culling tiles come from the
//! footprint pass over those tiles' pixels, `cull` keeps per map only the triangles that can change
//! a tested texel, and the raster draws those. Each tested pixel's outcome is the whole mesh's, so
//! V is unchanged (docs/gpu-frame.md §7).

use crate::gpu::readback;
use crate::gpu::structs::GpuSample;
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::render::shadow_raster::{RasterJob, ShadowMapArray};
use crate::stages::adaptive_buffers::CULL_TILE_WORDS;
use crate::stages::cull::{Cull, CullBatch};
use crate::stages::footprint::Footprint;
use crate::stages::raster::RasterTarget;
use crate::stages::shade::GeometryTiles;
use crate::stages::FrameGpu;
use crate::Result;

const SAMPLE_BYTES: u64 = std::mem::size_of::<GpuSample>() as u64;

pub(crate) struct CulledMaps {
    cull: Cull,
    footprint: Footprint,
    /// The batch's sample records, slot n holding its n-th map's: footprint, cull and the raster
    /// all read slot n (the draw's first instance is the slot).
    batch_samples: wgpu::Buffer,
    /// CULL_TILE_WORDS per slot.
    tiles: wgpu::Buffer,
    /// Indices each sample's map kept, by sample index (run.json's triangles per map).
    kept: wgpu::Buffer,
}

impl CulledMaps {
    /// For maps of sample indices below `samples`.
    pub(crate) fn new(fg: &FrameGpu, samples: u32) -> Result<Self> {
        let ctx = fg.ctx;
        // A batch's culling tiles are bound whole (256 KiB a map): a batch holds no more maps than
        // one binding's worth (512 on a 128 MiB binding), however many the grid has.
        let tile_bytes = CULL_TILE_WORDS as u64 * 4;
        let max_slots = (ctx
            .limits()
            .max_storage_buffer_binding_size
            .min(ctx.limits().max_buffer_size)
            / tile_bytes)
            .max(1) as u32;
        let cull = Cull::new(ctx, fg.scene, &fg.scene_gpu, samples.min(max_slots))?
            .ok_or_else(|| crate::Error::Limit("cull = on: this adapter cannot draw indirectly with a first instance, or one mesh copy does not fit a storage binding".into()))?;
        let slots = cull.slots as u64;
        Ok(Self {
            footprint: Footprint::new(ctx)?,
            batch_samples: readback::zeroed_storage(ctx, "batch samples", slots * SAMPLE_BYTES),
            tiles: readback::zeroed_storage(
                ctx,
                "footprint tiles",
                slots * CULL_TILE_WORDS as u64 * 4,
            ),
            kept: readback::zeroed_storage(ctx, "indices kept per sample", samples as u64 * 4),
            cull,
        })
    }

    /// Rasterizes `jobs` (their `sample` indexes `samples`) into `array`, batch by batch: footprint,
    /// cull, then each map draws what it kept. `frame`: the frame uniform with the maps' size.
    /// `tested`: the tiles whose pixels test these maps (the frame's geometry tiles, or a
    /// `regions` group's), whose pixels alone raise the culling tiles: a map then keeps only the
    /// triangles those pixels can see change, and the footprint costs their pixels, not the
    /// frame's. A list in bands falls back to every geometry pixel (the same V either way).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record(
        &self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        frame: &wgpu::Buffer,
        samples: &wgpu::Buffer,
        array: &ShadowMapArray,
        jobs: &[RasterJob],
        tested: &GeometryTiles,
    ) -> Result<()> {
        let ctx = fg.ctx;
        for batch in jobs.chunks(self.cull.slots as usize) {
            let n = batch.len() as u32;
            timer.stage(ctx, Stage::FOOTPRINT, |enc| {
                for (slot, j) in batch.iter().enumerate() {
                    enc.copy_buffer_to_buffer(
                        samples,
                        j.sample as u64 * SAMPLE_BYTES,
                        &self.batch_samples,
                        slot as u64 * SAMPLE_BYTES,
                        SAMPLE_BYTES,
                    );
                }
                enc.clear_buffer(&self.tiles, 0, Some(n as u64 * CULL_TILE_WORDS as u64 * 4));
                let batch = CullBatch {
                    samples: &self.batch_samples,
                    tiles: &self.tiles,
                };
                if !self
                    .footprint
                    .record_listed(ctx, enc, frame, &fg.gbuffer, &batch, n, tested)
                {
                    self.footprint
                        .record(ctx, enc, frame, &fg.gbuffer, &batch, n);
                }
                Ok(())
            })?;
            let slots: Vec<u32> = (0..n).collect();
            timer.stage(ctx, Stage::CULL, |enc| {
                self.cull.record(
                    ctx,
                    enc,
                    frame,
                    &fg.scene_gpu,
                    &CullBatch {
                        samples: &self.batch_samples,
                        tiles: &self.tiles,
                    },
                    &slots,
                );
                Ok(())
            })?;
            timer.stage(ctx, fg.raster.stage(), |enc| {
                let drawn: Vec<(RasterJob, u64)> = batch
                    .iter()
                    .enumerate()
                    .map(|(slot, j)| {
                        (
                            RasterJob {
                                sample: slot as u32,
                                ..*j
                            },
                            Cull::args_offset(slot as u32),
                        )
                    })
                    .collect();
                fg.raster.record_culled(
                    ctx,
                    enc,
                    &RasterTarget {
                        scene: &fg.scene_gpu,
                        samples: &self.batch_samples,
                        array,
                    },
                    &drawn,
                    &self.cull.culled,
                    &self.cull.args,
                )?;
                for (slot, j) in batch.iter().enumerate() {
                    enc.copy_buffer_to_buffer(
                        &self.cull.args,
                        Cull::args_offset(slot as u32),
                        &self.kept,
                        j.sample as u64 * 4,
                        4,
                    );
                }
                Ok(())
            })?;
        }
        Ok(())
    }

    /// Triangles each of `samples`' maps rasterized in the last frame (a read-back: after the frame).
    pub(crate) fn triangles(&self, fg: &FrameGpu, samples: &[u32]) -> Result<Vec<u64>> {
        let end = samples.iter().max().map_or(0, |&k| k as u64 + 1);
        let kept: Vec<u32> = readback::read_buffer(fg.ctx, &self.kept, end.max(4) * 4)?;
        Ok(samples
            .iter()
            .map(|&k| kept[k as usize] as u64 / 3)
            .collect())
    }
}
