//! The adaptive method's shadow maps: where each new map lives (layer, array) and how it is
//! rasterized (whole, scissored, culled) and, under scope = global, cached by shadow_test.

use super::context::Frame;
use super::AdaptiveTrace;
use crate::gpu::structs::GpuSample;
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::methods::adaptive::buffers::LATTICE_POINTS;
use crate::methods::hybrid_maps::HybridMaps;
use crate::render::kept_maps::{MapKey, Redraw, Slots};
use crate::render::shadow_raster::{RasterJob, ShadowMapArray};
use crate::stages::cull::{Cull, CullBatch};
use crate::stages::raster::RasterTarget;
use crate::stages::shadow_test::TestFrame;
use crate::stages::FrameGpu;
use crate::Result;

/// Shadow maps for the adaptive method: `global` reuses one array chunk by chunk (maps are needed
/// only until shadow_test has cached them); `local` keeps every map alive in up to two arrays.
/// Where the renderer reuses maps (docs/reuse.md), `slots` keeps each lattice sample's map across
/// frames: a frame rasterizes only the samples whose maps no layer holds.
pub(super) struct MapStore {
    pub(crate) arrays: Vec<ShadowMapArray>,
    pub(crate) per_array: u32,
    pub(crate) used: u32,
    /// `maps = hybrid` (scope = global): a few raster layers merged into a store, tested, dropped.
    pub(crate) hybrid: Option<HybridMaps>,
    /// Which key each layer holds (`keeps` off: every map is drawn).
    pub(crate) slots: Slots,
}

impl MapStore {
    pub(crate) fn views(&self) -> [&wgpu::TextureView; 2] {
        let a = &self.arrays[0].array_view;
        [a, self.arrays.get(1).map(|x| &x.array_view).unwrap_or(a)]
    }

    /// With `keeps`: the layer holding `key`, else the least recently used one outside `busy`
    /// (the current chunk's, or under scope = local every layer this frame used).
    fn kept_slot(&self, key: &MapKey, local: bool, busy: &[u32]) -> u32 {
        let busy = |s: u32| busy.contains(&s) || (local && self.slots.used_now(s));
        match self.slots.find(key) {
            Some(s) if !busy(s) => s,
            _ => self
                .slots
                .least_recent(busy)
                .expect("a chunk never needs more layers than the store holds"),
        }
    }
}

/// What a level asks of the map store: the lattice samples it renders, and (scope = local with
/// scissor) the texel rectangle each sample's pixels test.
pub(super) struct NewMaps<'a> {
    pub(super) new: &'a [u32],
    pub(super) rects: Option<&'a [[u32; 4]]>,
}

/// Rasterizes the maps of `new` (sorted, so layer assignment is deterministic) and, under
/// scope = global, caches their shadow tests; chunks when more maps than one array holds.
/// `keep` (tests) reads every map back into the trace.
pub(super) fn render_new(
    fx: &Frame,
    timer: &mut StageTimer,
    store: &mut MapStore,
    samples: &mut [GpuSample],
    request: NewMaps,
    trace: &mut AdaptiveTrace,
    keep: bool,
) -> Result<()> {
    let NewMaps { new, rects } = request;
    let (fg, b, local) = (fx.fg, fx.b, fx.local);
    let ctx = fg.ctx;
    let mut ks = new.to_vec();
    ks.sort_unstable();
    if let Some(h) = store.hybrid.as_mut() {
        return render_new_hybrid(fx, timer, h, samples, &ks, trace, keep);
    }
    let map_size = fg.scene.render.shadow_map_size;
    // A point light's lattice sample is `faces` maps (its cube, records k + 289 f): a chunk holds
    // whole cubes (scope = global only).
    let faces = super::faces_per_sample(samples);
    let capacity = if local {
        store.per_array
    } else {
        store.slots.capacity().max(1)
    };
    for chunk in ks.chunks((capacity / faces).max(1) as usize) {
        let mut jobs: Vec<(usize, RasterJob)> = Vec::new();
        let mut redraw: Vec<(usize, RasterJob)> = Vec::new();
        let mut busy = Vec::new();
        for (n, &k) in chunk.iter().enumerate() {
            for f in 0..faces {
                let i = (k + LATTICE_POINTS * f) as usize;
                let key = MapKey::of(&samples[i], map_size);
                let slot = if store.slots.keeps() {
                    store.kept_slot(&key, local, &busy)
                } else if local {
                    store.used + n as u32
                } else {
                    n as u32 * faces + f
                };
                busy.push(slot);
                let (array, layer) = (slot / store.per_array, slot % store.per_array);
                samples[i].layer = layer;
                samples[i].array = array;
                match store.slots.place(key, slot) {
                    Redraw::Kept => {}
                    Redraw::Rect(r) => redraw.push((
                        array as usize,
                        RasterJob {
                            sample: i as u32,
                            layer,
                            scissor: Some(r),
                        },
                    )),
                    Redraw::Whole => {
                        let scissor = rects.and_then(|r| scissor_rect(r[k as usize], map_size));
                        // A map none of whose pixels is tested needs no raster at all: an empty rect.
                        let skip = rects.is_some() && scissor.is_none();
                        if !skip {
                            jobs.push((
                                array as usize,
                                RasterJob {
                                    sample: i as u32,
                                    layer,
                                    scissor,
                                },
                            ));
                        }
                    }
                }
                ctx.queue.write_buffer(
                    &b.samples,
                    i as u64 * std::mem::size_of::<GpuSample>() as u64,
                    bytemuck::bytes_of(&samples[i]),
                );
            }
        }
        if local {
            store.used += chunk.len() as u32;
        }
        for (a, array) in store.arrays.iter().enumerate() {
            let again: Vec<RasterJob> = redraw
                .iter()
                .filter(|(x, _)| *x == a)
                .map(|(_, j)| *j)
                .collect();
            if !again.is_empty() {
                timer.stage(ctx, fg.raster.stage(), |enc| {
                    fg.raster.record_redraw(
                        ctx,
                        enc,
                        &RasterTarget {
                            scene: &fg.scene_gpu,
                            samples: &b.samples,
                            array,
                        },
                        samples,
                        &again,
                    )
                })?;
            }
            let mine: Vec<RasterJob> = jobs
                .iter()
                .filter(|(x, _)| *x == a)
                .map(|(_, j)| *j)
                .collect();
            if mine.is_empty() {
                continue;
            }
            if let Some(culled) = fx.passes.culled_maps.as_ref() {
                culled.record(
                    fg,
                    timer,
                    &fg.frame_buffer,
                    &b.samples,
                    array,
                    &mine,
                    &fg.geometry_tiles,
                )?;
                trace.culled.extend(mine.iter().map(|j| j.sample));
                continue;
            }
            let Some((cull, kept)) = fx.cull else {
                timer.stage(ctx, fg.raster.stage(), |enc| {
                    fg.raster.record(
                        ctx,
                        enc,
                        &RasterTarget {
                            scene: &fg.scene_gpu,
                            samples: &b.samples,
                            array,
                        },
                        &mine,
                    )?;
                    Ok(())
                })?;
                continue;
            };
            // Batches of slots: cull, then draw what each slot kept (the GPU writes the counts).
            for batch in mine.chunks(cull.slots as usize) {
                let ks: Vec<u32> = batch.iter().map(|j| j.sample).collect();
                timer.stage(ctx, Stage::CULL, |enc| {
                    cull.record(
                        ctx,
                        enc,
                        &fg.frame_buffer,
                        &fg.scene_gpu,
                        &CullBatch {
                            samples: &b.samples,
                            tiles: &b.footprints.tiles,
                        },
                        &ks,
                    );
                    Ok(())
                })?;
                timer.stage(ctx, fg.raster.stage(), |enc| {
                    let drawn: Vec<(RasterJob, u64)> = batch
                        .iter()
                        .enumerate()
                        .map(|(n, j)| (*j, Cull::args_offset(n as u32)))
                        .collect();
                    fg.raster.record_culled(
                        ctx,
                        enc,
                        &RasterTarget {
                            scene: &fg.scene_gpu,
                            samples: &b.samples,
                            array,
                        },
                        &drawn,
                        &cull.culled,
                        &cull.args,
                    )?;
                    for (n, &k) in ks.iter().enumerate() {
                        enc.copy_buffer_to_buffer(
                            &cull.args,
                            Cull::args_offset(n as u32),
                            kept,
                            k as u64 * 4,
                            4,
                        );
                    }
                    Ok(())
                })?;
                trace.culled.extend_from_slice(&ks);
            }
        }
        if !local {
            timer.stage(ctx, Stage::SHADOW_TEST, |enc| {
                fx.passes.shadow_test.record(
                    ctx,
                    enc,
                    &fx.test_frame(),
                    &store.arrays[0].array_view,
                    chunk,
                );
                Ok(())
            })?;
        }
        // Sample records of the next chunk overwrite this one's layers: submit before writing them.
        timer.flush(ctx);
        if keep {
            for &k in chunk {
                let s = &samples[k as usize];
                let map = crate::gpu::readback::read_texture(
                    ctx,
                    &store.arrays[s.array as usize].texture,
                    s.layer,
                    4,
                )?;
                trace.maps.push((k, map));
            }
        }
        trace.rendered.extend_from_slice(chunk);
    }
    Ok(())
}

/// `render_new` with `maps = hybrid` (scope = global): each batch of the transient raster is merged
/// into the store, tested by shadow_test (slot = lattice index) and dropped.
fn render_new_hybrid(
    fx: &Frame,
    timer: &mut StageTimer,
    maps: &mut HybridMaps,
    samples: &mut [GpuSample],
    ks: &[u32],
    trace: &mut AdaptiveTrace,
    keep: bool,
) -> Result<()> {
    let (fg, b) = (fx.fg, fx.b);
    let ctx = fg.ctx;
    let mut test =
        |fg: &FrameGpu, timer: &mut StageTimer, view: &wgpu::TextureView, slots: &[u32]| {
            timer.stage(ctx, Stage::SHADOW_TEST, |enc| {
                let t = TestFrame {
                    frame: &fg.frame_buffer,
                    gbuffer: &fg.gbuffer,
                    tiles: &fg.geometry_tiles,
                    rq: b.requests(),
                    out: &b.masks,
                };
                fx.passes.shadow_test.record(ctx, enc, &t, view, slots);
                Ok(())
            })
        };
    for chunk in ks.chunks(maps.layers() as usize) {
        for &k in chunk {
            samples[k as usize].layer = k;
            samples[k as usize].array = 0;
            ctx.queue.write_buffer(
                &b.samples,
                k as u64 * std::mem::size_of::<GpuSample>() as u64,
                bytemuck::bytes_of(&samples[k as usize]),
            );
        }
        maps.render(fg, timer, &b.samples, chunk, &mut test)?;
        maps.flush(fg, timer, &mut test)?;
        if keep {
            // Tests only: the maps as the lookup reads them (the pool keeps them until the next build).
            timer.flush(ctx);
            let pool = maps.store.read_words(ctx, maps.store.capacity_words)?;
            let h = maps.store.settings;
            for &k in chunk {
                trace.maps.push((
                    k,
                    crate::stages::hybrid_pool::decode(&pool, k, h.base, h.levels),
                ));
            }
        }
        trace.rendered.extend_from_slice(chunk);
    }
    Ok(())
}

/// Texel rectangle [min, max] → scissor (x, y, w, h), one texel of margin; None when empty.
fn scissor_rect(r: [u32; 4], size: u32) -> Option<[u32; 4]> {
    if r[0] > r[2] || r[1] > r[3] {
        return None;
    }
    let x0 = r[0].saturating_sub(1);
    let y0 = r[1].saturating_sub(1);
    let x1 = (r[2] + 2).min(size);
    let y1 = (r[3] + 2).min(size);
    Some([x0, y0, x1 - x0, y1 - y0])
}
