//! Adaptive light-source sampling (seed 000 / Schwärzler et al. 2012), GPU-driven per level:
//!   shadow_raster (new samples) ─► shadow_test ─► reproject_count ─► neighbourhood ─► quad_count
//!   ─► subdivide [─► compact under scope = local] ─► one small read-back ─► next level.
//! scope = global shades every pixel with every map (the seed); scope = local refines each pixel only
//! inside the quads whose penumbra it lies in (method.md §4.2).

pub(crate) mod buffers;
mod context;
mod frame;
mod growth;
mod levels;
mod maps;
pub(crate) mod params;
mod pictures;
mod record;
mod steer;
mod weights;

pub use frame::level_uniform;
pub use levels::LevelReport;
// LEVEL_LCM mirrors weights.wgsl's (tests/kernels.rs checks them).
pub use weights::{lattice_numerators, sample_weights, LEVEL_LCM};

use super::culled_maps::CulledMaps;
use super::hybrid_maps::{self, HybridMaps};
use super::{AdaptiveParams, Family, MethodInfo, MethodOutput, MethodState, Scope, ShadowMethod};
use crate::gpu::readback;
use crate::gpu::structs::GpuSample;
use crate::gpu::timing::StageTimer;
use crate::methods::adaptive::buffers::{AdaptiveBuffers, LATTICE_POINTS, LATTICE_SIDE};
use crate::render::kept_maps::{KeptMaps, ReuseCounts, Slots};
use crate::render::shadow_raster;
use crate::stages::FrameGpu;
use crate::stages::{
    compact::Compact, cull::Cull, neighbourhood::Neighbourhood, probe::Probe,
    quad_count::QuadCount, reproject_count::ReprojectCount, shadow_test::ShadowTest,
    subdivide::Subdivide,
};
use crate::{Error, Result};

pub(crate) const INFO: MethodInfo = MethodInfo {
    name: "adaptive",
    family: Family::MultiSample,
    summary: "adaptive light-source sampling (seed 000): split light quads whose penumbra pixels exceed p_m",
    // Each parameter's declaration (params.rs) is read by the parser and this listing alike.
    params: params::LISTED,
    parse: |p| Ok(std::sync::Arc::new(Adaptive(AdaptiveParams::from_map(p)?))),
};

/// The adaptive method with its parameters.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Adaptive(pub AdaptiveParams);

impl ShadowMethod for Adaptive {
    fn unsupported_light(&self, kind: crate::scene::LightKind) -> Option<&'static str> {
        // The point's six faces per lattice sample go through scope = global's waiting loop only.
        if super::cube_maps(kind) {
            return (self.0.scope == Scope::Local || self.0.cull == Some(true))
                .then_some(super::ONE_MAP_PER_POINT);
        }
        (!super::maps_from_the_emitter(kind)).then_some(super::ON_A_RECTANGLE)
    }
    fn unsupported_maps(
        &self,
        kind: crate::scene::LightKind,
        maps: crate::scene::MapKind,
    ) -> Option<&'static str> {
        (super::cube_maps(kind) && maps == crate::scene::MapKind::Hybrid)
            .then_some(super::CUBE_MAPS_ARE_PLAIN)
    }
    fn name(&self) -> &'static str {
        "adaptive"
    }
    fn label(&self) -> String {
        self.0.label()
    }
    fn params_json(&self) -> serde_json::Value {
        serde_json::to_value(&self.0).unwrap_or_default()
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        Ok(Box::new(State {
            p: self.0.clone(),
            prepared: prepare(fg, &self.0)?,
            pending: None,
            keep: false,
            trace: None,
            held: None,
        }))
    }
    /// At most the lattice's maps (`prepare`'s store).
    fn shadow_maps(&self, scene: &crate::scene::Scene) -> u32 {
        LATTICE_POINTS * crate::methods::faces(scene)
    }
    fn size_needs(
        &self,
        scene: &crate::scene::Scene,
        limits: &wgpu::Limits,
    ) -> Vec<crate::gpu::size_plan::SizeNeed> {
        // Global scope binds V and the masks by bands of rows (stages::shade::Band); local scope's
        // item passes reach any pixel, so there they are bound whole.
        let local = self.0.scope == Scope::Local;
        let mut needs = vec![crate::methods::sizes::visibility(scene, !local, limits)];
        needs.extend(buffers::size_needs(scene, local, limits));
        needs
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// Built once per scene and settings; `reset` zero-fills the buffers and restores the samples.
struct State {
    p: AdaptiveParams,
    prepared: Prepared,
    /// A GPU-steered frame's record, read in `finish`.
    pending: Option<steer::Pending>,
    /// Tests: every map and each level's masks (and consulted samples) go into the trace; the
    /// frame is host-steered, since only a level read-back sees them.
    keep: bool,
    /// The last frame's trace, for `inspect`.
    trace: Option<AdaptiveTrace>,
    /// The quads the previous frame split (one bit per quad node), for the hysteresis (`hold`);
    /// None before the first frame: every quad then counts as split, so it decides without a margin.
    held: Option<Vec<u32>>,
}

/// The quads a frame split, one bit per quad node (`quad_node`): the parents of each level's children.
pub fn split_quads(levels: &[LevelReport]) -> Vec<u32> {
    let mut bits = vec![0u32; crate::stages::adaptive_buffers::HELD_WORDS as usize];
    for child in levels.iter().flat_map(|l| &l.next_quads) {
        let size = child.size * 2;
        let node = crate::stages::adaptive_buffers::quad_node(
            child.i - child.i % size,
            child.j - child.j % size,
            size,
        );
        bits[(node / 32) as usize] |= 1 << (node % 32);
    }
    bits
}

impl MethodState for State {
    fn reset(&mut self, fg: &FrameGpu) -> Result<()> {
        let pr = &mut self.prepared;
        pr.samples = lattice_samples(fg, &self.p);
        fg.ctx
            .queue
            .write_buffer(&pr.b.samples, 0, bytemuck::cast_slice(&pr.samples));
        pr.store.used = 0;
        pr.store.slots.begin_frame();
        let held = self.held.clone().unwrap_or_else(|| {
            vec![u32::MAX; crate::stages::adaptive_buffers::HELD_WORDS as usize]
        });
        fg.ctx
            .queue
            .write_buffer(&pr.b.decisions.held, 0, bytemuck::cast_slice(&held));
        if let Some(h) = pr.store.hybrid.as_mut() {
            h.reset(fg);
        }
        pr.b.reset_frame(fg.ctx)
    }
    fn run(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        pictures: bool,
    ) -> Result<MethodOutput> {
        self.trace = None;
        if !self.keep && self.prepared.steer.is_some() {
            let (out, pending) = steer::run(fg, timer, &self.p, &mut self.prepared, pictures)?;
            self.pending = Some(pending);
            return Ok(out);
        }
        let (mut out, trace) =
            frame::run(fg, timer, &self.p, &mut self.prepared, self.keep, pictures)?;
        self.held = Some(split_quads(&trace.levels));
        self.trace = Some(trace);
        if self.p.scope == Scope::Local {
            self.prepared
                .growth
                .report(self.prepared.b.shape.item_capacity, &mut out)?;
        }
        Ok(out)
    }
    fn finish(&mut self, fg: &FrameGpu, out: &mut MethodOutput) -> Result<()> {
        if let Some(pending) = self.pending.take() {
            let trace = steer::finish(fg, &self.p, &mut self.prepared, pending, out)?;
            self.held = Some(split_quads(&trace.levels));
            self.trace = Some(trace);
            if self.p.scope == Scope::Local {
                self.prepared
                    .growth
                    .report(self.prepared.b.shape.item_capacity, out)?;
            }
        }
        Ok(())
    }
    /// After a frame that overflowed the item list: a list grown from what the overflowing level
    /// appended (`growth::next_capacity`); the other buffers, maps, pipelines and steering state
    /// do not depend on it. False when growth is off or the overflow was not the
    /// item list's; an overflow error of its own when the list already holds what one binding can.
    fn grow(&mut self, fg: &FrameGpu) -> Result<bool> {
        let pr = &mut self.prepared;
        let Some(needed) = pr.growth.needed.take() else {
            return Ok(false);
        };
        if !self.p.items_grow || pr.growth.fixed {
            return Ok(false);
        }
        let max = buffers::max_items(fg.ctx);
        let Some(capacity) = growth::next_capacity(pr.b.shape.item_capacity, needed, max) else {
            return Err(Error::Overflow(format!(
                "adaptive scope=local at {}x{}: a level needs at least {needed} (pixel, quad) items, more than the {max} one storage binding holds on this device; the run is not valid (use a smaller resolution, a lower max_level or scope=global)",
                fg.gbuffer.width, fg.gbuffer.height
            )));
        };
        pr.b.grow_items(fg.ctx, capacity)?;
        pr.growth.grown.push(capacity);
        self.pending = None;
        Ok(true)
    }
    fn buffer_sizes(&self) -> Vec<(String, u64)> {
        self.prepared.b.screen_sized()
    }
    /// The waiting loop's count of maps rendered and kept (the steered loop and hybrid maps keep
    /// none: every map rendered).
    fn reuse(&self) -> Option<ReuseCounts> {
        let c = self.prepared.store.slots.counts;
        (c.rendered + c.kept + c.redrawn > 0).then_some(c)
    }
    fn release_maps(&mut self) -> Vec<KeptMaps> {
        let store = &mut self.prepared.store;
        if !store.slots.keeps() {
            return Vec::new();
        }
        let size = store.arrays.first().map_or(0, |a| a.texture.width());
        let slots = std::mem::replace(&mut store.slots, Slots::new(0, false));
        vec![KeptMaps {
            owner: "adaptive".into(),
            size,
            arrays: std::mem::take(&mut store.arrays),
            slots,
        }]
    }
    fn keep_intermediates(&mut self) {
        self.keep = true;
    }
    /// With hysteresis, the quads this frame split: the next frame's state starts from them.
    fn memory(&self) -> Option<serde_json::Value> {
        (self.p.hold > 0).then(|| serde_json::json!({ "held": self.held }))
    }
    fn recall(&mut self, memory: &serde_json::Value) {
        self.held = serde_json::from_value(memory["held"].clone())
            .ok()
            .flatten();
    }
    /// The last frame's [`AdaptiveTrace`] (every frame keeps one; `keep_intermediates` adds the
    /// maps and per-level buffers).
    fn inspect(&mut self, _fg: &FrameGpu) -> Result<Option<Box<dyn std::any::Any>>> {
        Ok(self
            .trace
            .clone()
            .map(|t| Box::new(t) as Box<dyn std::any::Any>))
    }
}

/// The whole light, level 0's one quad.
pub(super) const ROOT: crate::gpu::structs::GpuQuad = crate::gpu::structs::GpuQuad {
    i: 0,
    j: 0,
    size: 16,
    parent: u32::MAX,
};
/// Its corners, the samples level 0 renders.
pub(super) const CORNERS: [u32; 4] = [
    lattice_index(0, 0),
    lattice_index(16, 0),
    lattice_index(0, 16),
    lattice_index(16, 16),
];

/// Lattice indices level `d` can render, ascending: level 0 the light's corners; level d ≥ 1 the
/// points of the level-d grid (spacing 2^(4−d)) that are not on the level-(d−1) grid. A quad that
/// splits at level d−1 requests only such points (its edge midpoints and centre).
pub(crate) fn candidates(d: u32) -> Vec<u32> {
    if d == 0 {
        return CORNERS.to_vec();
    }
    let step = 16 >> d;
    let mut out = Vec::new();
    for j in (0..=16).step_by(step as usize) {
        for i in (0..=16).step_by(step as usize) {
            if i % (2 * step) != 0 || j % (2 * step) != 0 {
                out.push(lattice_index(i, j));
            }
        }
    }
    out
}

/// Lattice index of (i, j).
pub(crate) const fn lattice_index(i: u32, j: u32) -> u32 {
    j * LATTICE_SIDE + i
}

/// Views of all 289 lattice samples (layer and array are filled in when a map is rendered).
pub(crate) fn lattice_samples(fg: &FrameGpu, p: &AdaptiveParams) -> Vec<GpuSample> {
    let s = fg.scene;
    // The quad tree lives on the unit square; the disk, the sun, the spot and the point take its
    // points through the concentric map, which keeps area, so the area weights stay right. A point
    // light's sample is six cube faces: face f of lattice sample k is record k + 289 f, so records
    // 0..289 are face 0's and every kernel that reads one record per lattice sample reads those.
    let faces: Vec<Vec<GpuSample>> = (0..LATTICE_POINTS)
        .map(|k| {
            let (i, j) = (k % LATTICE_SIDE, k / LATTICE_SIDE);
            s.emitter.sample_maps(
                &s.light,
                p.light_coord(i),
                p.light_coord(j),
                &s.bounds,
                s.render.shadow_map_size,
                k,
            )
        })
        .collect();
    (0..faces[0].len())
        .flat_map(|f| faces.iter().map(move |k| k[f]))
        .collect()
}

/// Maps per lattice sample: six for a point light's cube, else one (`lattice_samples`).
pub(crate) fn faces_per_sample(samples: &[GpuSample]) -> u32 {
    samples.len() as u32 / LATTICE_POINTS
}

/// Everything a test may want to see of one run besides the visibility image.
#[derive(Clone, Debug, Default)]
pub struct AdaptiveTrace {
    pub levels: Vec<LevelReport>,
    /// Lattice indices in the order their maps were rendered.
    pub rendered: Vec<u32>,
    pub weights: Vec<f32>,
    /// Captured for twin tests: each rendered map (lattice index, row-major depths).
    pub maps: Vec<(u32, Vec<f32>)>,
    /// The sample records as the kernels saw them (layer and array filled in).
    pub samples: Vec<GpuSample>,
    /// Triangles rasterized per map, in `rendered` order (the whole mesh unless culled).
    pub triangles: Vec<u64>,
    /// Lattice indices whose maps were drawn from a culled index list.
    pub culled: Vec<u32>,
}

/// Buffers, shadow-map arrays and pipelines, allocated (and zero-filled) before the frame's clock
/// starts, as a renderer would keep them from frame to frame.
pub(crate) struct Prepared {
    b: AdaptiveBuffers,
    store: maps::MapStore,
    passes: Passes,
    samples: Vec<GpuSample>,
    /// scope = local with culling: the index slots, and the indices kept per lattice sample
    /// (copied from the draw arguments, read back with each level).
    cull: Option<(Cull, wgpu::Buffer)>,
    /// The GPU-steered loop's state, where this setting allows it (steer::eligible).
    steer: Option<steer::Steer>,
    /// scope = local: what frames that overflowed the item list asked for (`State::grow`).
    growth: growth::Growth,
}

pub(crate) fn prepare(fg: &FrameGpu, p: &AdaptiveParams) -> Result<Prepared> {
    let ctx = fg.ctx;
    let scene = fg.scene;
    let local = p.scope == Scope::Local;
    let (w, h) = (fg.gbuffer.width, fg.gbuffer.height);
    let samples = lattice_samples(fg, p);
    let fixed = if p.items.is_none() && local {
        growth::fixed_from_env()?
    } else {
        None
    };
    let b = AdaptiveBuffers::new(ctx, w, h, &samples, local, p.items.or(fixed))?;
    b.zero_fill(ctx)?;
    let hybrid = scene.render.maps == crate::scene::MapKind::Hybrid;
    if hybrid && local {
        return Err(Error::Param(
            "adaptive: maps = hybrid needs scope = global (scope = local keeps every map alive for probe and reproject_count, which read depth arrays)".into(),
        ));
    }
    let per_array = fg.raster.maps_per_array(
        ctx,
        scene.render.shadow_map_size,
        scene.render.shadow_map_budget_mib,
    )?;
    // Maps kept from frame to frame (docs/reuse.md): not hybrid ones (merged into a store and
    // dropped), nor those that serve only this frame's pixels (scissored or culled), nor the
    // GPU-steered loop's (every candidate's layer is fixed before the frame).
    let faces = faces_per_sample(&samples);
    // What changes a map with the pixels (scissor, culling, a steered one-face frame) cannot be kept.
    let varies = hybrid
        || p.scissor
        || p.culls()
        || p.culls_every_pixel()
        || (faces == 1 && steer::eligible(p, &b));
    let keeps = fg.maps_kept.on && !varies;
    let size = scene.render.shadow_map_size;
    let taken = |layers: &[u32]| {
        fg.maps_kept
            .take("adaptive", size, layers)
            .filter(|_| keeps)
    };
    let store = if hybrid {
        // Maps live only until shadow_test has cached them: one raster batch per store.
        let maps = HybridMaps::new(fg, LATTICE_POINTS, hybrid_maps::TRANSIENT_LAYERS)?;
        maps::MapStore {
            arrays: Vec::new(),
            per_array: maps.layers(),
            used: 0,
            hybrid: Some(maps),
            slots: Slots::new(0, false),
        }
    } else if local {
        // Every map stays alive: the lattice needs up to 289, split across two arrays at the layer limit.
        let need = LATTICE_POINTS;
        let budget_maps = per_array as u64 * if per_array >= need { 1 } else { 2 };
        if (budget_maps as u32) < need && per_array < ctx.limits().max_texture_array_layers {
            return Err(Error::Limit(format!(
                "adaptive scope=local keeps every map alive: up to 289 maps of {0}x{0} do not fit shadow_map_budget_mib = {1}; raise the budget or use scope=global",
                scene.render.shadow_map_size, scene.render.shadow_map_budget_mib
            )));
        }
        let first = per_array.min(need);
        let layers: Vec<u32> = if first < need {
            vec![first, need - first]
        } else {
            vec![first]
        };
        kept_store(fg, taken(&layers), &layers, first, keeps)?
    } else {
        // With reuse, room for every lattice map the budget allows (a point light's six faces each).
        let chunk = per_array.min(if keeps {
            LATTICE_POINTS * faces
        } else {
            LATTICE_POINTS
        });
        kept_store(fg, taken(&[chunk]), &[chunk], chunk, keeps)?
    };
    let passes = Passes {
        shadow_test: if faces_per_sample(&samples) > 1 {
            ShadowTest::new_cube(fg.ctx, fg.map_access())?
        } else {
            ShadowTest::new(fg.ctx, fg.map_access(), local)?
        },
        reproject_count: ReprojectCount::new(ctx)?,
        neighbourhood: Neighbourhood::new(ctx)?,
        quad_count: QuadCount::new(ctx)?,
        subdivide: Subdivide::new(ctx)?,
        compact: Compact::new(ctx)?,
        probe: Probe::new(ctx)?,
        culled_maps: if p.culls_every_pixel() {
            Some(CulledMaps::new(fg, LATTICE_POINTS)?)
        } else {
            None
        },
    };
    if hybrid && p.culls_every_pixel() {
        return Err(crate::Error::Param("adaptive: cull = on under scope = global rasterizes plain maps; it cannot run with maps = hybrid".into()));
    }
    let cull = if p.culls() {
        Cull::new(ctx, fg.scene, &fg.scene_gpu, LATTICE_POINTS)?.map(|c| {
            (
                c,
                readback::zeroed_storage(
                    ctx,
                    "culled indices per sample",
                    LATTICE_POINTS as u64 * 4,
                ),
            )
        })
    } else {
        None
    };
    // maps = hybrid merges each batch into a store whose allocation the CPU reads: it waits.
    // cull = on (global) culls between the waiting loop's levels: the steered loop does not.
    let cube = faces_per_sample(&samples) > 1;
    if cube && hybrid {
        return Err(Error::Param(format!(
            "adaptive: {}",
            super::CUBE_MAPS_ARE_PLAIN
        )));
    }
    let steer = if !hybrid && !cube && !p.culls_every_pixel() && steer::eligible(p, &b) {
        Some(steer::Steer::new(fg, p, &b)?)
    } else {
        None
    };
    Ok(Prepared {
        b,
        store,
        passes,
        samples,
        cull,
        steer,
        growth: growth::Growth {
            fixed: fixed.is_some(),
            ..Default::default()
        },
    })
}

/// The store's arrays: those the renderer kept, or new ones cleared to the far plane.
fn kept_store(
    fg: &FrameGpu,
    kept: Option<KeptMaps>,
    layers: &[u32],
    per_array: u32,
    keeps: bool,
) -> Result<maps::MapStore> {
    let (arrays, slots) = match kept {
        Some(k) => (k.arrays, k.slots),
        None => {
            let arrays: Vec<_> = layers
                .iter()
                .map(|&l| {
                    fg.raster
                        .allocate(fg.ctx, fg.scene.render.shadow_map_size, l)
                })
                .collect();
            for array in &arrays {
                shadow_raster::clear_all(fg.ctx, array)?;
            }
            (arrays, Slots::new(layers.iter().sum(), keeps))
        }
    };
    Ok(maps::MapStore {
        arrays,
        per_array,
        used: 0,
        hybrid: None,
        slots,
    })
}

/// The adaptive stages' pipelines, built once per method.
struct Passes {
    shadow_test: ShadowTest,
    reproject_count: ReprojectCount,
    neighbourhood: Neighbourhood,
    quad_count: QuadCount,
    subdivide: Subdivide,
    compact: Compact,
    probe: Probe,
    /// cull = on under scope = global: footprint, cull and the culled raster.
    culled_maps: Option<CulledMaps>,
}
