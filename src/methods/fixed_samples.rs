//! Methods with a fixed sample set (hard, regular): raster every map, shade, chunk by chunk when the
//! maps exceed the memory budget or the layer limit. With `maps = hybrid` the maps are rasterized a
//! few at a time and merged into a hybrid store, which is shaded whenever it is full.

use super::culled_maps::CulledMaps;
use super::hybrid_maps::{HybridMaps, HybridRecord};
use super::{
    Family, MethodInfo, MethodOutput, MethodState, Param, ParamDecl, ParamMap, ShadowMethod,
    SwitchDecl,
};
use crate::gpu::readback;
use crate::gpu::structs::GpuSample;
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::render::kept_maps::{KeptMaps, MapKey, Redraw, ReuseCounts, Slots};
use crate::render::shadow_raster::{self, RasterJob};
use crate::stages::raster::RasterTarget;
use crate::stages::shade::{GeometryTiles, TILE_LIST_HEADER};
use crate::stages::FrameGpu;
use crate::Result;

pub(crate) const HARD: MethodInfo = MethodInfo {
    name: "hard",
    family: Family::Hard,
    summary: "one shadow map from the light's centre, one binary test per pixel",
    params: &[],
    parse: |_| Ok(std::sync::Arc::new(Fixed::Hard)),
};

/// regular's grid side.
pub(crate) const N: ParamDecl<u32> = ParamDecl::new(
    "n",
    "17",
    1,
    128,
    "samples per side, 1..=128 (17 gives the 289 lattice points)",
);

pub(crate) const CULL: SwitchDecl = SwitchDecl::new(
    "cull",
    false,
    "on: raster each map only with the triangles that can change a texel some geometry pixel tests (the same V; docs/gpu-frame.md)",
);
pub(crate) const ESTIMATE: SwitchDecl = SwitchDecl::new(
    "estimate",
    false,
    "on: predict the frame's error without a reference (run.json predicted_rmse, predicted_sampling, predicted_map, error-bound.png; docs/error-estimate.md)",
);

pub(crate) const REGULAR: MethodInfo = MethodInfo {
    name: "regular",
    family: Family::MultiSample,
    summary: "N×N shadow maps on the light's lattice corners, equal weights",
    params: &[
        N.param(),
        Param { key: "layout", default: "lattice", help: "lattice (corners i/(N−1)), centred (cell centres) or jittered (one seeded point per cell)" },
        CULL.param(),
        ESTIMATE.param(),
    ],
    parse: |p: &ParamMap| {
        let n = N.get(p, "regular")?;
        let layout = match p.get("layout").map(String::as_str) {
            None | Some("lattice") => Layout::Lattice,
            Some("centred") | Some("centered") => Layout::Centred,
            Some("jittered") => Layout::Jittered,
            Some(v) => return Err(crate::Error::Param(format!("regular: layout = `{v}`: use `lattice`, `centred` or `jittered`"))),
        };
        let cull = CULL.get(p, "regular")?;
        let estimate = ESTIMATE.get(p, "regular")?;
        if estimate && cull {
            return Err(crate::Error::Param("regular: estimate = on reads texels around each lookup, which cull = on may leave out; use one of them".into()));
        }
        Ok(std::sync::Arc::new(Fixed::Regular { n, layout, cull, estimate }))
    },
};

/// Hard (one map from the centre) or the regular N×N grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Fixed {
    Hard,
    /// `cull`: each map rasterizes only what can change a tested texel (`CulledMaps`).
    /// `estimate`: the frame also predicts its own error (`methods::estimate`).
    Regular {
        n: u32,
        layout: Layout,
        cull: bool,
        estimate: bool,
    },
}

impl Fixed {
    pub(crate) fn points(&self) -> Vec<(f32, f32)> {
        match self {
            Fixed::Hard => vec![(0.5, 0.5)],
            Fixed::Regular { n, layout, .. } => regular_points(*n, *layout),
        }
    }
}

impl ShadowMethod for Fixed {
    fn unsupported_light(&self, kind: crate::scene::LightKind) -> Option<&'static str> {
        // The disk's lattice and the sun's directions are the square's through the concentric map
        // (`Emitter::sample_map`); hard takes its centre.
        let why = match self {
            Fixed::Hard => super::FROM_THE_CENTRE,
            Fixed::Regular { .. } => super::ON_A_RECTANGLE,
        };
        (!(super::maps_from_the_emitter(kind) || super::cube_maps(kind))).then_some(why)
    }
    fn name(&self) -> &'static str {
        match self {
            Fixed::Hard => "hard",
            Fixed::Regular { .. } => "regular",
        }
    }
    fn label(&self) -> String {
        match self {
            Fixed::Hard => "hard".into(),
            Fixed::Regular {
                n,
                layout,
                cull,
                estimate,
            } => {
                let layout = match layout {
                    Layout::Lattice => "",
                    Layout::Centred => ",layout=centred",
                    Layout::Jittered => ",layout=jittered",
                };
                format!(
                    "regular:n={n}{layout}{}{}",
                    if *cull { ",cull=on" } else { "" },
                    if *estimate { ",estimate=on" } else { "" }
                )
            }
        }
    }
    fn params_json(&self) -> serde_json::Value {
        match self {
            Fixed::Hard => serde_json::json!({}),
            Fixed::Regular {
                n,
                layout,
                cull,
                estimate,
            } => {
                serde_json::json!({ "n": n, "layout": layout, "cull": cull, "estimate": estimate })
            }
        }
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        let cull = matches!(self, Fixed::Regular { cull: true, .. });
        if cull && fg.scene.render.maps == crate::scene::MapKind::Hybrid {
            return Err(crate::Error::Param(
                "regular: cull = on rasterizes plain maps; it cannot run with maps = hybrid".into(),
            ));
        }
        let mut prepared = prepare_kept(
            fg,
            &self.points(),
            fg.scene.render.shadow_map_size,
            None,
            Some("fixed"),
        )?;
        if cull {
            prepared.cull(fg)?;
        }
        if let Fixed::Regular {
            n,
            layout,
            estimate: true,
            ..
        } = *self
        {
            prepared.estimate = Some(Estimate::new(fg, n, layout, prepared.points)?);
        }
        Ok(Box::new(prepared))
    }
    /// One map per light point (six per point for a point light's cube faces).
    fn shadow_maps(&self, scene: &crate::scene::Scene) -> u32 {
        self.points().len() as u32 * crate::methods::faces(scene)
    }
    /// Shade binds V by bands of rows (stages::shade::Band): any resolution whose V fits one buffer.
    fn size_needs(
        &self,
        scene: &crate::scene::Scene,
        limits: &wgpu::Limits,
    ) -> Vec<crate::gpu::size_plan::SizeNeed> {
        vec![crate::methods::sizes::visibility(scene, true, limits)]
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

impl MethodState for Prepared {
    fn reset(&mut self, fg: &FrameGpu) -> Result<()> {
        // Every raster pass clears its layer; the estimate's sums start at zero.
        if let Some(e) = &self.estimate {
            e.clear(fg)?;
        }
        Ok(())
    }
    /// The estimate's sums, read after the clock stopped: the prediction and the bound picture.
    fn finish(&mut self, fg: &FrameGpu, out: &mut MethodOutput) -> Result<()> {
        let Some(e) = &self.estimate else {
            return Ok(());
        };
        let sums = e.read(fg)?;
        let geometry = geometry_mask(fg)?;
        let (prediction, bound) = e.predict(&sums, &geometry)?;
        // Kept for `inspect` (the twin test, and the estimate study's per-pixel bound).
        let kept = self.kept.get_or_insert_with(FixedBuffers::default);
        kept.estimate_sums = sums;
        kept.split = e.split.clone();
        let fields =
            serde_json::to_value(prediction).map_err(|err| crate::Error::Limit(err.to_string()))?;
        for (k, v) in fields.as_object().into_iter().flatten() {
            out.record[k] = v.clone();
        }
        out.bound = Some(bound);
        Ok(())
    }
    fn run(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        _pictures: bool,
    ) -> Result<MethodOutput> {
        run(fg, timer, self)
    }
    fn keep_intermediates(&mut self) {
        self.keep = true;
    }
    /// The last frame's [`FixedBuffers`], when `keep_intermediates` was called before it; with
    /// `estimate = on` and without it, the estimate's sums alone.
    fn inspect(&mut self, _fg: &FrameGpu) -> Result<Option<Box<dyn std::any::Any>>> {
        Ok(self
            .kept
            .take()
            .map(|c| Box::new(c) as Box<dyn std::any::Any>))
    }
    fn reuse(&self) -> Option<ReuseCounts> {
        self.reuse_counts()
    }
    fn release_maps(&mut self) -> Vec<KeptMaps> {
        self.release().into_iter().collect()
    }
}

/// Light points (s, t) of the regular N×N grid in `layout` (docs/method.md §7):
/// - lattice: the corners i/(N-1), edges included, so N = 17 gives exactly the 289 points of §3
///   (N = 1 is the centre); the mean over a closed lattice weights the light's boundary too much;
/// - centred: the cell centres (i+½)/N, the midpoint rule;
/// - jittered: one point per cell at (i+u)/N, u uniform from a fixed seed (stratified sampling).
pub fn regular_points(n: u32, layout: Layout) -> Vec<(f32, f32)> {
    let cells = move |offset: &dyn Fn(u32, u32) -> (f32, f32)| -> Vec<(f32, f32)> {
        (0..n)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .map(|(i, j)| {
                let (u, v) = offset(i, j);
                ((i as f32 + u) / n as f32, (j as f32 + v) / n as f32)
            })
            .collect()
    };
    match layout {
        Layout::Lattice if n == 1 => vec![(0.5, 0.5)],
        Layout::Lattice => {
            let step = 1.0 / (n - 1) as f32;
            (0..n)
                .flat_map(|j| (0..n).map(move |i| (i as f32 * step, j as f32 * step)))
                .collect()
        }
        Layout::Centred => cells(&|_, _| (0.5, 0.5)),
        Layout::Jittered => cells(&|i, j| {
            let h = splitmix64(JITTER_SEED ^ ((j as u64) << 32 | i as u64));
            (
                (h >> 40) as f32 / (1u64 << 24) as f32,
                ((h >> 16) & 0xff_ffff) as f32 / (1u64 << 24) as f32,
            )
        }),
    }
}

/// Where the N×N grid's points sit in their cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Layout {
    Lattice,
    Centred,
    Jittered,
}

/// The fixed seed of `layout = jittered`, so runs repeat exactly.
const JITTER_SEED: u64 = 0x005e_ed0f_9e11;

fn splitmix64(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

impl Prepared {
    /// Maps per frame (six per sample of a point light).
    pub(crate) fn map_count(&self) -> usize {
        self.points
    }

    /// New sample records for the same points (the regions' windows, fitted anew each frame),
    /// in the layers `prepare_sized` gave them.
    pub(crate) fn set_samples(
        &mut self,
        ctx: &crate::gpu::GpuContext,
        mut samples: Vec<GpuSample>,
    ) {
        for (new, old) in samples.iter_mut().zip(&self.samples) {
            new.layer = old.layer;
        }
        ctx.queue
            .write_buffer(&self.samples_buffer, 0, bytemuck::cast_slice(&samples));
        self.samples = samples;
    }

    /// Shade (and nothing else) runs on `tiles` instead of the frame's geometry tiles.
    pub(crate) fn set_tiles(&mut self, tiles: GeometryTiles) {
        self.tiles = Some(tiles);
    }

    /// Each map rasterizes only the triangles that can change a tested texel (`CulledMaps`). Such
    /// a map serves this frame's pixels alone, so none is kept.
    pub(crate) fn cull(&mut self, fg: &FrameGpu) -> Result<()> {
        self.culled = Some(CulledMaps::new(fg, self.points as u32)?);
        if let Maps::Plain(k, _) = &mut self.maps {
            k.slots = Slots::new(k.slots.capacity(), false);
        }
        Ok(())
    }

    /// The last frame's maps rendered and kept (None with hybrid maps, which keep none).
    pub(crate) fn reuse_counts(&self) -> Option<ReuseCounts> {
        match &self.maps {
            Maps::Plain(k, _) => Some(k.slots.counts),
            _ => None,
        }
    }

    /// Its maps for the renderer to keep (`MethodState::release_maps`); the state runs no frame after.
    pub(crate) fn release(&mut self) -> Option<KeptMaps> {
        match std::mem::replace(&mut self.maps, Maps::Released) {
            Maps::Plain(k, _) => Some(k),
            other => {
                self.maps = other;
                None
            }
        }
    }
}

/// Where a fixed sample set's maps go and in which chunks they are drawn and shaded. Without
/// reuse (or where all fit): chunks of the array's `capacity`, map i in layer i mod capacity. With
/// reuse and more maps than fit, the first `pinned` maps keep their own layers from frame to frame
/// and the rest take turns in the other `rotating` layers (drawn every frame): the eviction
/// docs/reuse.md states.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Placement {
    pub(crate) points: u32,
    pub(crate) pinned: u32,
    pub(crate) rotating: u32,
}

impl Placement {
    pub(crate) fn new(points: u32, capacity: u32, keeps: bool) -> Placement {
        let capacity = capacity.max(1);
        if !keeps {
            return Placement {
                points,
                pinned: 0,
                rotating: capacity,
            };
        }
        if points <= capacity {
            return Placement {
                points,
                pinned: points,
                rotating: capacity - points,
            };
        }
        // A quarter of the layers turn over (at least one), the rest are kept.
        let rotating = (capacity / 4).max(1);
        Placement {
            points,
            pinned: capacity - rotating,
            rotating,
        }
    }

    /// Map i's layer.
    pub(crate) fn layer(&self, i: u32) -> u32 {
        if i < self.pinned {
            i
        } else {
            self.pinned + (i - self.pinned) % self.rotating
        }
    }

    /// (first, count) of each chunk, in sample order.
    pub(crate) fn chunks(&self) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        if self.pinned > 0 {
            out.push((0, self.pinned.min(self.points)));
        }
        let mut first = self.pinned;
        while first < self.points {
            let count = self.rotating.max(1).min(self.points - first);
            out.push((first, count));
            first += count;
        }
        out
    }
}

/// Buffers and the maps of a fixed-sample run, allocated before the frame's clock starts.
pub(crate) struct Prepared {
    /// Maps per frame: the samples, six per sample of a point light.
    points: usize,
    samples: Vec<GpuSample>,
    weights: Vec<f32>,
    samples_buffer: wgpu::Buffer,
    weights_buffer: wgpu::Buffer,
    maps: Maps,
    /// `cull = on`: the passes that cull each map's triangles.
    culled: Option<CulledMaps>,
    /// `estimate = on`: the error estimate's pass and buffers.
    pub(crate) estimate: Option<Estimate>,
    /// The frame uniform of another map size than the scene's (`prepare_sized`).
    frame: Option<wgpu::Buffer>,
    /// The tiles shade runs on; None: the frame's geometry tiles (the regions' classes shade
    /// their own).
    tiles: Option<GeometryTiles>,
    /// Tests: every chunk's maps are kept, since the next chunk overwrites them.
    keep: bool,
    kept: Option<FixedBuffers>,
}

/// Plain: one array, whose layers `Placement` hands out, shaded chunk by chunk. Hybrid: a
/// transient raster and a store. Released: given to the renderer to keep (the state is dropped).
enum Maps {
    Plain(KeptMaps, Placement),
    Hybrid(Box<HybridMaps>),
    Released,
}

/// `prepare` with plain maps of `map_size` instead of the scene's, and `frame` (the frame uniform
/// with that map size) for every pass that reads them: one renderer tries several map sizes
/// (`methods::auto`). `frame` None: the frame's own.
pub(crate) fn prepare_sized(
    fg: &FrameGpu,
    points: &[(f32, f32)],
    map_size: u32,
    frame: Option<wgpu::Buffer>,
) -> Result<Prepared> {
    prepare_kept(fg, points, map_size, frame, None)
}

/// `prepare_sized` whose maps are kept from frame to frame as `owner`'s where the renderer
/// reuses maps (docs/reuse.md): it takes what the renderer kept of them.
pub(crate) fn prepare_kept(
    fg: &FrameGpu,
    points: &[(f32, f32)],
    map_size: u32,
    frame: Option<wgpu::Buffer>,
    owner: Option<&str>,
) -> Result<Prepared> {
    let ctx = fg.ctx;
    let s = &fg.scene;
    let hybrid = s.render.maps == crate::scene::MapKind::Hybrid;
    if hybrid && frame.is_some() {
        return Err(crate::Error::Param(
            "a map size other than the scene's runs on plain maps (maps = plain)".into(),
        ));
    }
    // A point light's sample is six maps (its cube faces): layers, chunks and the budget count maps.
    let mut samples: Vec<GpuSample> = points
        .iter()
        .flat_map(|&(u, v)| {
            s.emitter
                .sample_maps(&s.light, u, v, &s.bounds, map_size, u32::MAX)
        })
        .collect();
    let chunk = if hybrid {
        u32::MAX
    } else {
        fg.raster
            .maps_per_array(ctx, map_size, s.render.shadow_map_budget_mib)?
            .min(samples.len() as u32)
            .max(1)
    };
    if !hybrid && frame.is_some() {
        // A map side the method chose at run time (regions, auto): the plan could not see this
        // array before the frame, so it goes through the plan's heap check here.
        crate::methods::sizes::check_run_time_array(ctx, &s.render, map_size, chunk)?;
    }
    let keeps = owner.is_some() && fg.maps_kept.on && !hybrid;
    let placement = Placement::new(samples.len() as u32, chunk, keeps);
    for (i, g) in samples.iter_mut().enumerate() {
        // Hybrid: the layer is the sample's slot in the store.
        g.layer = if hybrid {
            i as u32
        } else {
            placement.layer(i as u32)
        };
    }
    // Each face of a cube carries its sample's weight: the lookup counts one face per receiver.
    let weights = vec![1.0 / points.len() as f32; samples.len()];
    let points = samples.len();
    let samples_buffer =
        readback::storage_buffer(ctx, "samples", &samples, wgpu::BufferUsages::empty());
    let weights_buffer =
        readback::storage_buffer(ctx, "weights", &weights, wgpu::BufferUsages::empty());
    let maps = if hybrid {
        Maps::Hybrid(Box::new(HybridMaps::new(fg, points as u32, points as u32)?))
    } else {
        let owner = owner.unwrap_or("fixed");
        let kept = match fg.maps_kept.take(owner, map_size, &[chunk]) {
            Some(k) if keeps => k,
            _ => {
                let array = fg.raster.allocate(ctx, map_size, chunk);
                shadow_raster::clear_all(ctx, &array)?;
                KeptMaps {
                    owner: owner.to_string(),
                    size: map_size,
                    arrays: vec![array],
                    slots: Slots::new(chunk, keeps),
                }
            }
        };
        Maps::Plain(kept, placement)
    };
    Ok(Prepared {
        points,
        samples,
        weights,
        samples_buffer,
        weights_buffer,
        maps,
        culled: None,
        estimate: None,
        frame,
        tiles: None,
        keep: false,
        kept: None,
    })
}

/// Renders and shades chunk by chunk; with `keep`, every map and sample record is kept for the
/// shade twin (tests only).
fn run(fg: &FrameGpu, timer: &mut StageTimer, prepared: &mut Prepared) -> Result<MethodOutput> {
    let Prepared {
        points,
        samples,
        weights,
        samples_buffer,
        weights_buffer,
        maps,
        culled,
        estimate,
        frame,
        tiles,
        keep,
        kept,
    } = prepared;
    let tiles = tiles.as_ref().unwrap_or(&fg.geometry_tiles);
    let estimate = estimate.as_ref();
    let frame = frame.as_ref().unwrap_or(&fg.frame_buffer);
    let (kept_maps, placement) = match maps {
        Maps::Plain(k, p) => (k, *p),
        Maps::Hybrid(h) => {
            return run_hybrid(
                fg,
                timer,
                *points,
                samples,
                weights,
                samples_buffer,
                weights_buffer,
                h,
                estimate,
                *keep,
                kept,
            )
        }
        Maps::Released => {
            return Err(crate::Error::Gpu(
                "a fixed-sample state ran a frame after giving its maps away".into(),
            ))
        }
    };
    let KeptMaps {
        arrays,
        slots,
        size: map_size,
        ..
    } = kept_maps;
    let array = &arrays[0];
    let map_size = *map_size;
    slots.begin_frame();
    let ctx = fg.ctx;
    let points = *points;
    let mut buffers = keep.then(FixedBuffers::default);
    let inputs = crate::stages::shade::ShadeInputs {
        frame,
        samples: samples_buffer,
        weights: weights_buffer,
        gbuffer: &fg.gbuffer,
        tiles,
        visibility: &fg.visibility,
    };
    let bar = crate::progress::bar(points as u64, "shadow maps");
    let chunks = placement.chunks();
    for &(first, count) in &chunks {
        // Only what the layers do not hold already (every map, where nothing is kept).
        let (mut jobs, mut redraw) = (Vec::new(), Vec::new());
        for i in first..first + count {
            let layer = placement.layer(i);
            match slots.place(MapKey::of(&samples[i as usize], map_size), layer) {
                Redraw::Kept => {}
                Redraw::Rect(r) => redraw.push(RasterJob {
                    sample: i,
                    layer,
                    scissor: Some(r),
                }),
                Redraw::Whole => jobs.push(RasterJob {
                    sample: i,
                    layer,
                    scissor: None,
                }),
            }
        }
        match culled.as_ref() {
            Some(c) => c.record(fg, timer, frame, samples_buffer, array, &jobs, tiles)?,
            None if jobs.is_empty() && redraw.is_empty() => {}
            None => timer.stage(ctx, fg.raster.stage(), |enc| {
                let target = RasterTarget {
                    scene: &fg.scene_gpu,
                    samples: samples_buffer,
                    array,
                };
                fg.raster.record(ctx, enc, &target, &jobs)?;
                fg.raster.record_redraw(ctx, enc, &target, samples, &redraw)
            })?,
        }
        if let Some(c) = buffers.as_mut() {
            timer.flush(ctx);
            for i in first..first + count {
                c.maps.push(readback::read_texture(
                    ctx,
                    &array.texture,
                    placement.layer(i),
                    4,
                )?);
            }
        }
        timer.stage(ctx, Stage::SHADE, |enc| {
            fg.shade
                .record(ctx, enc, &inputs, &array.array_view, first, count);
            Ok(())
        })?;
        if let Some(e) = estimate {
            e.record(
                fg,
                timer,
                frame,
                samples_buffer,
                weights_buffer,
                &array.array_view,
                first,
                count,
            )?;
        }
        bar.inc(count as u64);
    }
    bar.finish_and_clear();
    if let Some(c) = buffers.as_mut() {
        c.samples = samples.clone();
        c.weights = weights.clone();
        c.tiles = read_tiles(fg, tiles)?;
    }
    slots.commit();
    let chunk = chunks.iter().map(|c| c.1).max().unwrap_or(0);
    let mut record = FixedRecord {
        maps_per_chunk: chunk,
        chunks: chunks.len() as u32,
        ..FixedRecord::default()
    };
    let mut syncs = 0;
    match culled.as_ref() {
        Some(c) => {
            // The counts the GPU wrote: one read-back after the last map.
            timer.flush(ctx);
            let ks: Vec<u32> = (0..points as u32).collect();
            let triangles = timer.cpu(Stage::READBACK, || c.triangles(fg, &ks))?;
            syncs = 1;
            record.triangles_per_map_mean =
                Some(triangles.iter().sum::<u64>() as f64 / points as f64);
            record.triangles_per_map = Some(triangles);
            record.culled_maps = Some(points as u32);
        }
        // Every map rasterizes the whole mesh.
        None => record.triangles_per_map_mean = Some(fg.scene_gpu.index_count as f64 / 3.0),
    }
    let out = Ok(MethodOutput {
        shadow_maps: points as u32,
        syncs,
        record: super::record_value("regular", &record)?,
        pictures: Vec::new(),
        bound: None,
    });
    *kept = buffers;
    out
}

/// `run` with `maps = hybrid`: batches of the transient raster's layers, merged into the store; the
/// store is shaded whenever it is full and once at the end. Samples are contiguous, so each shade
/// is one range.
#[allow(clippy::too_many_arguments)]
fn run_hybrid(
    fg: &FrameGpu,
    timer: &mut StageTimer,
    points: usize,
    samples: &[GpuSample],
    weights: &[f32],
    samples_buffer: &wgpu::Buffer,
    weights_buffer: &wgpu::Buffer,
    maps: &mut HybridMaps,
    estimate: Option<&Estimate>,
    keep: bool,
    kept: &mut Option<FixedBuffers>,
) -> Result<MethodOutput> {
    let ctx = fg.ctx;
    maps.reset(fg);
    let inputs = fg.shade_inputs(samples_buffer, weights_buffer);
    let tiles = &fg.geometry_tiles;
    let mut consume =
        |fg: &FrameGpu, timer: &mut StageTimer, view: &wgpu::TextureView, slots: &[u32]| {
            debug_assert!(slots.windows(2).all(|w| w[1] == w[0] + 1));
            timer.stage(ctx, Stage::SHADE, |enc| {
                fg.shade
                    .record(ctx, enc, &inputs, view, slots[0], slots.len() as u32);
                Ok(())
            })?;
            match estimate {
                Some(e) => e.record(
                    fg,
                    timer,
                    &fg.frame_buffer,
                    samples_buffer,
                    weights_buffer,
                    view,
                    slots[0],
                    slots.len() as u32,
                ),
                None => Ok(()),
            }
        };
    let mut cap = keep.then(FixedBuffers::default);
    let layers = maps.layers();
    let bar = crate::progress::bar(points as u64, "shadow maps");
    for first in (0..points as u32).step_by(layers as usize) {
        let ks: Vec<u32> = (first..first + layers.min(points as u32 - first)).collect();
        let flushes = maps.stats.flushes;
        maps.render(fg, timer, samples_buffer, &ks, &mut consume)?;
        if let Some(c) = cap.as_mut() {
            // Tests only: the batch's full-resolution maps and the store that holds them.
            timer.flush(ctx);
            if maps.stats.flushes != flushes {
                return Err(crate::Error::Limit(
                    "keeping the maps with maps=hybrid needs a store that holds each raster batch"
                        .into(),
                ));
            }
            let pool = maps.store.read_words(ctx, maps.store.capacity_words)?;
            let (base, levels) = (maps.store.settings.base, maps.store.settings.levels);
            for (layer, &k) in ks.iter().enumerate() {
                c.raw_maps.push(readback::read_texture(
                    ctx,
                    &maps.raster.texture,
                    layer as u32,
                    4,
                )?);
                c.maps
                    .push(crate::stages::hybrid_pool::decode(&pool, k, base, levels));
            }
            c.hybrid_pool = pool;
        }
        bar.inc(ks.len() as u64);
    }
    maps.flush(fg, timer, &mut consume)?;
    bar.finish_and_clear();
    if let Some(c) = cap.as_mut() {
        c.samples = samples.to_vec();
        c.weights = weights.to_vec();
        c.tiles = read_tiles(fg, tiles)?;
    }
    let out = Ok(MethodOutput {
        shadow_maps: points as u32,
        syncs: maps.stats.syncs,
        record: super::record_value(
            "regular",
            &FixedRecord {
                maps_per_chunk: layers,
                chunks: maps.stats.flushes,
                hybrid: Some(maps.record()),
                ..FixedRecord::default()
            },
        )?,
        pictures: Vec::new(),
        bound: None,
    });
    *kept = cap;
    out
}

/// A fixed sample set's record in run.json (`method_record`); `estimate = on` adds the
/// prediction's fields after the frame (`finish`).
#[derive(Default, serde::Serialize)]
struct FixedRecord {
    /// Maps drawn and shaded together: the largest chunk (maps = hybrid: the raster's layers).
    maps_per_chunk: u32,
    /// Chunks drawn (maps = hybrid: times the store was handed to shade).
    chunks: u32,
    /// Plain maps: triangles each map rasterized, on average.
    #[serde(skip_serializing_if = "Option::is_none")]
    triangles_per_map_mean: Option<f64>,
    /// cull = on: the counts the GPU wrote, per map.
    #[serde(skip_serializing_if = "Option::is_none")]
    triangles_per_map: Option<Vec<u64>>,
    /// cull = on: maps drawn from a culled index list.
    #[serde(skip_serializing_if = "Option::is_none")]
    culled_maps: Option<u32>,
    /// maps = hybrid: the hybrid store's figures.
    #[serde(skip_serializing_if = "Option::is_none")]
    hybrid: Option<HybridRecord>,
}

/// Tests only: the listed tiles, sorted (the GPU appends them in any order).
fn read_tiles(fg: &FrameGpu, tiles: &GeometryTiles) -> Result<Vec<u32>> {
    let words: Vec<u32> = readback::read_buffer(fg.ctx, &tiles.list, tiles.bytes)?;
    let count = words[0] as usize;
    let mut list = words[TILE_LIST_HEADER..TILE_LIST_HEADER + count].to_vec();
    list.sort_unstable();
    Ok(list)
}

/// Maps, samples and weights of a fixed-sample run, for the shade twin. With `maps = hybrid`,
/// `maps` are what the lookup twin reads from the store, `raw_maps` the rasterized maps and
/// `hybrid_pool` the store after the last batch.
#[derive(Default)]
pub struct FixedBuffers {
    /// The tiles shade ran on (sorted), for the geometry_tiles twin.
    pub tiles: Vec<u32>,
    pub maps: Vec<Vec<f32>>,
    pub raw_maps: Vec<Vec<f32>>,
    pub hybrid_pool: Vec<u32>,
    pub samples: Vec<GpuSample>,
    pub weights: Vec<f32>,
    /// `estimate = on`: the sums after the frame, and each sample's half-set weights.
    pub estimate_sums: Vec<crate::stages::estimate::Sums>,
    pub split: Vec<[f32; 2]>,
}

/// `estimate = on`: the pass, each sample's half-set weights and the per-pixel sums.
pub(crate) struct Estimate {
    pass: crate::stages::estimate::EstimatePass,
    layout: Layout,
    /// The grid's side.
    n: u32,
    split: Vec<[f32; 2]>,
    split_buffer: wgpu::Buffer,
    sums: wgpu::Buffer,
}

impl Estimate {
    pub(crate) fn new(fg: &FrameGpu, n: u32, layout: Layout, maps: usize) -> Result<Estimate> {
        crate::stages::estimate::check_bands(
            &fg.geometry_tiles,
            fg.gbuffer.width,
            fg.gbuffer.height,
        )?;
        let split = super::estimate::split_weights(n, maps / (n * n) as usize);
        let split_buffer = readback::storage_buffer(
            fg.ctx,
            "estimate split",
            &split,
            wgpu::BufferUsages::empty(),
        );
        let sums = readback::zeroed_storage(
            fg.ctx,
            "estimate sums",
            fg.pixel_count() as u64 * crate::stages::estimate::SUM_BYTES,
        );
        Ok(Estimate {
            pass: crate::stages::estimate::EstimatePass::new(fg.ctx, fg.map_access())?,
            layout,
            n,
            split,
            split_buffer,
            sums,
        })
    }

    pub(crate) fn clear(&self, fg: &FrameGpu) -> Result<()> {
        let mut enc = fg.ctx.device.create_command_encoder(&Default::default());
        enc.clear_buffer(&self.sums, 0, None);
        fg.ctx.queue.submit([enc.finish()]);
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    fn record(
        &self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        frame: &wgpu::Buffer,
        samples: &wgpu::Buffer,
        weights: &wgpu::Buffer,
        maps: &wgpu::TextureView,
        first: u32,
        count: u32,
    ) -> Result<()> {
        let inputs = crate::stages::estimate::EstimateInputs {
            frame,
            samples,
            weights,
            split: &self.split_buffer,
            gbuffer: &fg.gbuffer,
            tiles: &fg.geometry_tiles,
            sums: &self.sums,
        };
        timer.stage(fg.ctx, Stage::ESTIMATE, |enc| {
            self.pass.record(fg.ctx, enc, &inputs, maps, first, count);
            Ok(())
        })
    }

    pub(crate) fn read(&self, fg: &FrameGpu) -> Result<Vec<crate::stages::estimate::Sums>> {
        readback::read_buffer(
            fg.ctx,
            &self.sums,
            fg.pixel_count() as u64 * crate::stages::estimate::SUM_BYTES,
        )
    }

    /// The frame's prediction and the bound's picture from the sums.
    pub(crate) fn predict(
        &self,
        sums: &[crate::stages::estimate::Sums],
        geometry: &[bool],
    ) -> Result<(super::estimate::Prediction, Vec<f32>)> {
        super::estimate::predict(sums, geometry, self.layout, self.n)
    }
}

/// The frame's geometry pixels, read back from the G-buffer.
pub(crate) fn geometry_mask(fg: &FrameGpu) -> Result<Vec<bool>> {
    let g = crate::render::gbuffer::read_back(fg.ctx, &fg.gbuffer)?;
    Ok((0..g.position.len()).map(|i| g.is_geometry(i)).collect())
}

#[cfg(test)]
mod tests {
    use super::{regular_points, FixedRecord, Layout};

    /// run.json's shape: entries a frame does not fill are absent, not null; the mean stays a
    /// float where it is whole.
    #[test]
    fn the_record_leaves_out_what_the_frame_did_not_fill() {
        let plain = FixedRecord {
            maps_per_chunk: 25,
            chunks: 1,
            triangles_per_map_mean: Some(12.0),
            ..FixedRecord::default()
        };
        assert_eq!(
            serde_json::to_string(&plain).unwrap(),
            r#"{"maps_per_chunk":25,"chunks":1,"triangles_per_map_mean":12.0}"#
        );
        let culled = FixedRecord {
            triangles_per_map: Some(vec![3, 4]),
            culled_maps: Some(2),
            triangles_per_map_mean: Some(3.5),
            ..plain
        };
        assert_eq!(
            serde_json::to_string(&culled).unwrap(),
            r#"{"maps_per_chunk":25,"chunks":1,"triangles_per_map_mean":3.5,"triangles_per_map":[3,4],"culled_maps":2}"#
        );
    }

    #[test]
    fn centred_and_jittered_are_stratified() {
        for layout in [Layout::Centred, Layout::Jittered] {
            let p = regular_points(9, layout);
            assert_eq!(p.len(), 81);
            for (k, (s, t)) in p.iter().enumerate() {
                let (i, j) = ((k % 9) as f32, (k / 9) as f32);
                assert!(
                    *s > i / 9.0 && *s < (i + 1.0) / 9.0 && *t > j / 9.0 && *t < (j + 1.0) / 9.0,
                    "{layout:?} point {k} ({s}, {t}) outside its cell"
                );
            }
        }
        assert_eq!(
            regular_points(2, Layout::Centred),
            vec![(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)]
        );
        let jitter = regular_points(9, Layout::Jittered);
        assert_eq!(
            jitter,
            regular_points(9, Layout::Jittered),
            "jittered is seeded, so runs repeat"
        );
        assert!(
            jitter
                .iter()
                .zip(regular_points(9, Layout::Centred))
                .filter(|(a, b)| **a != *b)
                .count()
                == 81
        );
    }

    #[test]
    fn regular_17_is_the_lattice() {
        let p = regular_points(17, Layout::Lattice);
        assert_eq!(p.len(), 289);
        for (k, (s, t)) in p.iter().enumerate() {
            assert_eq!(*s, (k % 17) as f32 / 16.0);
            assert_eq!(*t, (k / 17) as f32 / 16.0);
        }
    }
}
