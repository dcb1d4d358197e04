//! `maps = hybrid` for the map-reading methods (docs/hybrid.md): a transient full-resolution raster
//! of a few layers, merged map by map into a hybrid store. When the store is full its maps are
//! handed to the method (shade, shadow_test) and the store starts again, so the memory a method
//! holds is the raster's few layers plus the store, not a full-resolution layer per map.

use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::render::shadow_raster::{self, RasterJob, ShadowMapArray};
use crate::stages::hybrid_build::{HybridBuild, HybridStore};
use crate::stages::raster::RasterTarget;
use crate::stages::FrameGpu;
use crate::{Error, Result};

/// Full-resolution layers rasterized before they are merged (at most; fewer when the budget is small).
pub(crate) const TRANSIENT_LAYERS: u32 = 4;

/// Hands a method the store's view and the slots (sample indices) it holds.
pub(crate) type Consume<'c> =
    dyn FnMut(&FrameGpu, &mut StageTimer, &wgpu::TextureView, &[u32]) -> Result<()> + 'c;

pub(crate) struct HybridMaps {
    pub(crate) raster: ShadowMapArray,
    pub(crate) store: HybridStore,
    build: HybridBuild,
    /// Slots built into the store and not yet handed over.
    pending: Vec<u32>,
    /// Pool words in use after the last build.
    used: u32,
    pub(crate) stats: HybridStats,
}

/// run.json's `hybrid` entry of a method that reads hybrid maps (`HybridMaps::record`).
#[derive(Clone, Debug, serde::Serialize)]
pub(crate) struct HybridRecord {
    pub(crate) base: u32,
    pub(crate) levels: u32,
    /// Merge tolerance in 16-bit depth units.
    pub(crate) eps: f32,
    pub(crate) coarse: u32,
    pub(crate) maps: u32,
    pub(crate) bytes_per_map: f64,
    pub(crate) plain_bytes_per_map: f64,
    pub(crate) share_of_plain: f64,
    pub(crate) store_peak_bytes: u64,
    pub(crate) store_capacity_bytes: u64,
    pub(crate) build_scratch_bytes: u64,
    pub(crate) transient_layers: u32,
    pub(crate) transient_bytes: u64,
    pub(crate) flushes: u32,
    pub(crate) syncs: u32,
}

/// What one frame's maps cost (per frame; `record` writes it into run.json).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub(crate) struct HybridStats {
    pub(crate) maps: u32,
    /// Pool words of every map built (coarse grid and children, not the root words).
    pub(crate) words: u64,
    /// Times the store was emptied into the method (1 when every map fits at once).
    pub(crate) flushes: u32,
    /// Read-backs of the store's allocation state (one per raster batch, one more per overflow).
    pub(crate) syncs: u32,
    pub(crate) peak_words: u32,
}

/// Largest store a map can need: every coarse texel refined to full resolution.
fn worst_map_words(coarse: u64, levels: u32) -> u64 {
    coarse * coarse * if levels == 2 { 1 + 4 + 16 } else { 1 + 4 }
}

impl HybridMaps {
    /// Room for `slots` sample indices; `maps` is how many maps one store is meant to hold at once
    /// (the store is capped by the memory budget left after the transient raster).
    pub(crate) fn new(fg: &FrameGpu, slots: u32, maps: u32) -> Result<Self> {
        let ctx = fg.ctx;
        let r = &fg.scene.render;
        let h = r.hybrid;
        let layer_bytes = h.base as u64 * h.base as u64 * 4;
        let budget = r.shadow_map_budget_mib as u64 * 1024 * 1024;
        let layers = fg
            .raster
            .maps_per_array(ctx, h.base, r.shadow_map_budget_mib)?
            .min(TRANSIENT_LAYERS)
            .min(maps.max(1));
        let coarse = (h.base >> h.levels) as u64;
        let left = budget.saturating_sub(layers as u64 * layer_bytes);
        let wanted = (slots as u64 + maps as u64 * worst_map_words(coarse, h.levels)) * 4;
        let capacity = wanted.min(left);
        if capacity < (slots as u64 + coarse * coarse) * 4 {
            return Err(Error::Limit(format!(
                "maps=hybrid: {layers} transient {0}x{0} layer(s) leave {1} MiB of shadow_map_budget_mib = {2}, less than one {coarse}x{coarse} coarse grid; raise the budget or lower base",
                h.base,
                left / (1024 * 1024),
                r.shadow_map_budget_mib
            )));
        }
        let raster = fg.raster.allocate(ctx, h.base, layers);
        shadow_raster::clear_all(ctx, &raster)?;
        let store = HybridStore::new(ctx, h, slots, capacity)?;
        Ok(Self {
            raster,
            store,
            build: HybridBuild::new(ctx, fg.raster.raster_access())?,
            pending: Vec::new(),
            used: slots,
            stats: HybridStats::default(),
        })
    }

    /// Maps rasterized at once.
    pub(crate) fn layers(&self) -> u32 {
        self.raster.layers()
    }

    /// Starts a frame: an empty store and fresh statistics.
    pub(crate) fn reset(&mut self, fg: &FrameGpu) {
        self.pending.clear();
        self.store.reset(fg.ctx);
        self.used = self.store.slots;
        self.stats = HybridStats::default();
    }

    /// Rasterizes the maps of samples `ks` (at most `layers()`; sample index = slot) and merges them
    /// into the store. When the store overflows, `consume` gets the maps it holds, the store starts
    /// again and the rest of `ks` is merged from the raster, which still holds them.
    pub(crate) fn render(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        samples: &wgpu::Buffer,
        ks: &[u32],
        consume: &mut Consume,
    ) -> Result<()> {
        let ctx = fg.ctx;
        assert!(
            ks.len() <= self.layers() as usize,
            "a raster batch holds at most {} maps",
            self.layers()
        );
        let jobs: Vec<RasterJob> = ks
            .iter()
            .enumerate()
            .map(|(i, &k)| RasterJob {
                sample: k,
                layer: i as u32,
                scissor: None,
            })
            .collect();
        timer.stage(ctx, fg.raster.stage(), |enc| {
            fg.raster.record(
                ctx,
                enc,
                &RasterTarget {
                    scene: &fg.scene_gpu,
                    samples,
                    array: &self.raster,
                },
                &jobs,
            )?;
            Ok(())
        })?;
        let mut from = 0;
        while from < ks.len() {
            let (build, store, raster) = (&self.build, &self.store, &self.raster);
            timer.stage(ctx, Stage::HYBRID_BUILD, |enc| {
                for (i, &k) in ks.iter().enumerate().skip(from) {
                    build.record(ctx, enc, store, raster, i as u32, k);
                }
                Ok(())
            })?;
            timer.flush(ctx);
            let control = timer.cpu(Stage::HYBRID_BUILD, || self.store.read_control(ctx))?;
            self.stats.syncs += 1;
            let ok = control.built as usize - self.pending.len();
            self.pending.extend_from_slice(&ks[from..from + ok]);
            self.used = control.used;
            self.stats.peak_words = self.stats.peak_words.max(control.used);
            from += ok;
            if control.overflow == 0 {
                break;
            }
            if self.pending.is_empty() {
                let h = self.store.settings;
                return Err(Error::Limit(format!(
                    "maps=hybrid: one {0}x{0} map (levels {1}, eps {2}) needs more than the store's {3} MiB; raise shadow_map_budget_mib or eps",
                    h.base,
                    h.levels,
                    h.eps,
                    self.store.capacity_bytes() / (1024 * 1024)
                )));
            }
            self.flush(fg, timer, consume)?;
        }
        Ok(())
    }

    /// Hands every map in the store to `consume` and empties the store.
    pub(crate) fn flush(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        consume: &mut Consume,
    ) -> Result<()> {
        if self.pending.is_empty() {
            return Ok(());
        }
        consume(fg, timer, &self.store.view, &self.pending)?;
        self.stats.maps += self.pending.len() as u32;
        self.stats.words += (self.used - self.store.slots) as u64;
        self.stats.flushes += 1;
        self.pending.clear();
        self.store.reset(fg.ctx);
        self.used = self.store.slots;
        Ok(())
    }

    /// The run record's `hybrid` entry: settings, bytes per map against a plain map of the same
    /// resolution, the store and the transient raster.
    pub(crate) fn record(&self) -> HybridRecord {
        let h = self.store.settings;
        let st = &self.stats;
        // A map's bytes: its words in the pool plus its root word.
        let bytes_per_map = if st.maps == 0 {
            0.0
        } else {
            (st.words as f64 / st.maps as f64 + 1.0) * 4.0
        };
        let plain = h.base as f64 * h.base as f64 * 4.0;
        HybridRecord {
            base: h.base,
            levels: h.levels,
            eps: h.eps,
            coarse: self.store.coarse,
            maps: st.maps,
            bytes_per_map,
            plain_bytes_per_map: plain,
            share_of_plain: bytes_per_map / plain,
            store_peak_bytes: st.peak_words as u64 * 4,
            store_capacity_bytes: self.store.capacity_bytes(),
            build_scratch_bytes: self.store.scratch_bytes(),
            transient_layers: self.layers(),
            transient_bytes: self.layers() as u64 * plain as u64,
            flushes: st.flushes,
            syncs: st.syncs,
        }
    }
}
