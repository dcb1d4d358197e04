//! `regions`: each screen region gets its own samples per side and map size (docs/regions.md).
//! A blocker search on the centre map measures every pixel's penumbra width and footprint
//! (`stages::regions`); each region's count picks its class from a ladder of grids. One read-back
//! (the classes' counts, texel needs and boxes) separates the decision from the maps. A cost
//! model then joins each class into the next one up where one set of maps is cheaper than two;
//! each group's maps are a centred grid fitted to the box of its receivers, sized for the finest
//! texel its pixels need, culled per map, and shaded on that group's tiles alone.

pub(crate) mod budget;
mod certified;
pub(crate) mod pictures;
pub(crate) mod record;

use super::fixed_samples::{self, regular_points, Layout, Prepared};
use super::single_map::{light_size, CentreMap};
use super::{
    check_range, Family, MethodInfo, MethodOutput, MethodState, Param, ParamDecl, ParamMap,
    ShadowMethod, SwitchDecl,
};
use crate::gpu::readback;
use crate::gpu::structs::GpuSample;
use crate::gpu::timing::StageTimer;
use crate::gpu::Stage;
use crate::render::kept_maps::ReuseCounts;
use crate::scene::light::{sample_view_window, Bounds};
use crate::stages::regions::{
    unordered, RegionsInputs, RegionsParams, RegionsPass, CLASS_WORDS, MAX_CLASSES, REGION_WORDS,
};
use crate::stages::FrameGpu;
use crate::Result;
pub(crate) use record::ClassRecord;
use record::RegionsRecord;
use std::collections::HashMap;
use std::sync::Arc;

pub(crate) const TARGET: ParamDecl<f32> = ParamDecl::new(
    "target",
    "0.02",
    0.0005,
    0.5,
    "the frame's RMSE of V to meet: each region gets n = k·(P/A)^0.2 samples per side for P penumbra pixels of A, k from the target (docs/regions.md)",
);
pub(crate) const MAX_N: ParamDecl<u32> =
    ParamDecl::new("max_n", "16", 1, 64, "most samples per side, 1..=64");
/// `power_of_two` checks it.
pub(crate) const MIN_SIZE: ParamDecl<u32> = ParamDecl::new(
    "min_size",
    "64",
    0,
    u32::MAX,
    "smallest map side, a power of two, 16..=8192",
);
/// `power_of_two` checks it.
pub(crate) const MAX_SIZE: ParamDecl<u32> = ParamDecl::new(
    "max_size",
    "2048",
    0,
    u32::MAX,
    "largest map side, a power of two, 16..=8192",
);
pub(crate) const DENSITY: ParamDecl<f32> = ParamDecl::new(
    "density",
    "0",
    0.0,
    64.0,
    "texels per pixel footprint; 0: the least that meets the maps' share of the target (T/√2, docs/regions.md), and at least 1 + the lookup's offsets in texels (bias constant + slope + normal offset)",
);
pub(crate) const REGION: ParamDecl<u32> = ParamDecl::new(
    "region",
    "16",
    8,
    256,
    "region side in pixels, a multiple of 8 up to 256",
);
/// `power_of_two` checks it (0: derived).
pub(crate) const CENTRE_SIZE: ParamDecl<u32> = ParamDecl::new(
    "centre_size",
    "0",
    0,
    u32::MAX,
    "side of the decision's map from the light's centre, a power of two 16..=8192; 0: twice the screen's larger side, at most shadow_map_size (the blocker search reads penumbra widths, not edges)",
);
pub(crate) const BLOCKER_TAPS: ParamDecl<u32> = ParamDecl::new(
    "blocker_taps",
    "6",
    1,
    16,
    "blocker-search taps per side on the centre map, 1..=16",
);
pub(crate) const MAP_COST: ParamDecl<f32> = ParamDecl::new(
    "map_cost",
    "550000",
    0.0,
    1e9,
    "the cost model's price of one map beyond its texels, in texels (passes, culling, triangles; fitted on llvmpipe, docs/regions.md)",
);
pub(crate) const SAMPLE_COST: ParamDecl<f32> = ParamDecl::new(
    "sample_cost",
    "40",
    0.0,
    1e9,
    "the cost model's price of one pixel's test of one map, in texels",
);
/// `power_of_two` checks it (0: the scene's).
pub(crate) const FORCE_SIZE: ParamDecl<u32> = ParamDecl::new(
    "force_size",
    "0",
    0,
    u32::MAX,
    "map side with force = N; 0: the scene's shadow_map_size",
);
pub(crate) const PIXELS: ParamDecl<u32> = ParamDecl::new(
    "pixels",
    "256",
    16,
    8192,
    "certify = on: exact pixels drawn per class, 16..=8192",
);
pub(crate) const TRUTH_SIDE: ParamDecl<u32> = ParamDecl::new(
    "truth_side",
    "32",
    2,
    32,
    "certify = on: the exact pixels' stratified samples per side; 32: the reference's own 32 × 32; below: two independent m × m estimates per pixel (2m² rays), the product of their errors unbiased for e² (docs/regions.md, \"Certified classes\")",
);
/// `parse` checks the half-open range (0, 0.5].
pub(crate) const DELTA: ParamDecl<f32> = ParamDecl::new(
    "delta",
    "0.05",
    f32::MIN,
    f32::MAX,
    "certify = on: the frame's bound holds with probability 1 − delta (each class's at delta / classes), in (0, 0.5]",
);
/// `parse` checks it (0 or 0.0005..=0.5).
pub(crate) const PLAN_TARGET: ParamDecl<f32> = ParamDecl::new(
    "plan_target",
    "0",
    f32::MIN,
    f32::MAX,
    "the target the plan is decided for; 0: target (a larger one makes a plan that under-counts, for studying the measurement)",
);
pub(crate) const MERGE: SwitchDecl = SwitchDecl::new(
    "merge",
    true,
    "on: a class joins the next one up (its tiles get more samples, one set of maps for both) when the cost model predicts the joined maps cheaper; off: every class its own maps",
);
pub(crate) const HOLD: SwitchDecl = SwitchDecl::new(
    "hold",
    true,
    "on: a group keeps the previous frame's window, grown to the union with its receivers', while that window's extent stays within the band of what its receivers need (docs/reuse.md), and with certify a class starts from the setting the previous frame ended on (docs/regions.md, Certified classes, item 7); off: every frame fits its windows and decides afresh",
);
pub(crate) const CERTIFY: SwitchDecl = SwitchDecl::new(
    "certify",
    true,
    "on: each class's error is measured with the exact truth at pixels drawn within it and a class whose bound is over the target is stepped up; the frame is met only where the certified bound is at most the target (docs/regions.md, \"Certified classes\"); off: the plan alone, as decided",
);

pub(crate) const INFO: MethodInfo = MethodInfo {
    name: "regions",
    family: Family::MultiSample,
    summary: "per screen region: samples per side from its penumbra width, map texels from its footprint, maps fitted to its receivers",
    params: &[
        TARGET.param(),
        MAX_N.param(),
        MIN_SIZE.param(),
        MAX_SIZE.param(),
        DENSITY.param(),
        REGION.param(),
        CENTRE_SIZE.param(),
        BLOCKER_TAPS.param(),
        Param { key: "cull", default: "auto", help: "on: each map rasterizes only the triangles that can change a texel a pixel tests (the same V); auto: on where the adapter can cull (indirect draws with a first instance), off elsewhere; off" },
        MERGE.param(),
        MAP_COST.param(),
        SAMPLE_COST.param(),
        Param { key: "force", default: "off", help: "N: every region gets N×N centred samples on maps of force_size over the whole scene (V equals regular:n=N,layout=centred)" },
        FORCE_SIZE.param(),
        HOLD.param(),
        CERTIFY.param(),
        PIXELS.param(),
        TRUTH_SIDE.param(),
        DELTA.param(),
        Param { key: "filter", default: "pcss", help: "certify = on: a one-map filter each class may take where it is certified within the target (pcss, or none)" },
        Param { key: "fallback", default: "1.2", help: "certify = on: the frame-wide grid (the top class's samples on every tile) is taken where its predicted cost is at most this many times the plan's; off: never" },
        PLAN_TARGET.param(),
    ],
    parse,
};

/// The classes' samples per side: steps of about √2 in n (2× in maps) up to `max_n`.
const LADDER: [u32; 12] = [1, 2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64];

fn power_of_two(key: &str, v: u32) -> Result<u32> {
    let v = check_range("regions", key, v, 16, 8192)?;
    if !v.is_power_of_two() {
        return Err(crate::Error::Param(format!(
            "regions: {key} = {v} is not a power of two"
        )));
    }
    Ok(v)
}

fn parse(p: &ParamMap) -> Result<Arc<dyn ShadowMethod>> {
    let target = TARGET.get(p, "regions")?;
    let density = DENSITY.get(p, "regions")?;
    let region = REGION.get(p, "regions")?;
    if region % 8 != 0 {
        return Err(crate::Error::Param(format!(
            "regions: region = {region} is not a multiple of 8"
        )));
    }
    let (min_size, max_size) = (
        power_of_two("min_size", MIN_SIZE.get(p, "regions")?)?,
        power_of_two("max_size", MAX_SIZE.get(p, "regions")?)?,
    );
    if min_size > max_size {
        return Err(crate::Error::Param(format!(
            "regions: min_size = {min_size} is above max_size = {max_size}"
        )));
    }
    // None: auto. Culling never changes V, so a device that cannot cull renders the same frame uncut.
    let cull = match p.get("cull").map(String::as_str) {
        None | Some("auto") => None,
        Some("on") => Some(true),
        Some("off") => Some(false),
        Some(v) => {
            return Err(crate::Error::Param(format!(
                "regions: cull = `{v}`: use `on`, `off` or `auto`"
            )))
        }
    };
    let force = match p.get("force").map(String::as_str) {
        None | Some("off") => None,
        Some(v) => match v.parse::<u32>() {
            Ok(n) if (1..=128).contains(&n) => Some(n),
            _ => {
                return Err(crate::Error::Param(format!(
                    "regions: force = `{v}`: use `off` or samples per side 1..=128"
                )))
            }
        },
    };
    let merge = MERGE.get(p, "regions")?;
    let map_cost = MAP_COST.get(p, "regions")?;
    let sample_cost = SAMPLE_COST.get(p, "regions")?;
    let force_size = FORCE_SIZE.get(p, "regions")?;
    let hold = HOLD.get(p, "regions")?;
    let certify = CERTIFY.get(p, "regions")?;
    let pixels = PIXELS.get(p, "regions")?;
    let truth_side = TRUTH_SIDE.get(p, "regions")?;
    let delta = DELTA.get(p, "regions")?;
    if !(delta > 0.0 && delta <= 0.5) {
        return Err(crate::Error::Param(format!(
            "regions: delta = {delta} is outside (0, 0.5]"
        )));
    }
    let filter = match p.get("filter").map(String::as_str) {
        None | Some("pcss") => true,
        Some("none") => false,
        Some(v) => {
            return Err(crate::Error::Param(format!(
                "regions: filter = `{v}`: use `pcss` or `none`"
            )))
        }
    };
    let fallback = match p.get("fallback").map(String::as_str) {
        None => Some(1.2),
        Some("off") => None,
        Some(v) => match v.parse::<f32>() {
            Ok(r) if (1.0..=100.0).contains(&r) => Some(r),
            _ => {
                return Err(crate::Error::Param(format!(
                    "regions: fallback = `{v}`: use `off` or a cost ratio 1..=100"
                )))
            }
        },
    };
    let plan_target = PLAN_TARGET.get(p, "regions")?;
    if plan_target != 0.0 && !(0.0005..=0.5).contains(&plan_target) {
        return Err(crate::Error::Param(format!(
            "regions: plan_target = {plan_target} is outside 0.0005..=0.5 (or 0: target)"
        )));
    }
    let centre_size = match CENTRE_SIZE.get(p, "regions")? {
        0 => 0,
        v => power_of_two("centre_size", v)?,
    };
    if force_size != 0 {
        if force.is_none() {
            return Err(crate::Error::Param(format!(
                "regions: force_size = {force_size} needs force = N"
            )));
        }
        power_of_two("force_size", force_size)?;
    }
    Ok(Arc::new(Regions {
        target,
        density,
        max_n: MAX_N.get(p, "regions")?,
        min_size,
        max_size,
        region,
        blocker_taps: BLOCKER_TAPS.get(p, "regions")?,
        cull,
        merge,
        map_cost,
        sample_cost,
        force,
        force_size,
        centre_size,
        hold,
        certify,
        pixels,
        truth_side,
        delta,
        filter,
        fallback,
        plan_target,
    }))
}

#[derive(Clone, Debug, PartialEq)]
pub struct Regions {
    pub(crate) target: f32,
    pub(crate) density: f32,
    pub(crate) max_n: u32,
    pub(crate) min_size: u32,
    pub(crate) max_size: u32,
    pub(crate) region: u32,
    pub(crate) blocker_taps: u32,
    /// Some(on/off) as given; None: auto (on where the adapter can cull).
    pub(crate) cull: Option<bool>,
    /// Classes join the next one up where the cost model predicts it cheaper.
    pub(crate) merge: bool,
    /// The cost model's prices in texels: one map beyond its texels, one pixel's test of one map.
    pub(crate) map_cost: f32,
    pub(crate) sample_cost: f32,
    pub(crate) force: Option<u32>,
    pub(crate) force_size: u32,
    /// The decision's map side; 0: from the screen (`Regions::centre_side`).
    pub(crate) centre_size: u32,
    /// A group keeps the previous frame's window while it holds (`State::held_window`).
    pub(crate) hold: bool,
    /// Each class's error bounded against the exact truth and stepped up where over (certified/).
    pub(crate) certify: bool,
    /// Exact pixels drawn per class; the frame's confidence 1 − delta.
    pub(crate) pixels: u32,
    /// The exact pixels' samples per side: 32, the reference's; below, a paired estimate.
    pub(crate) truth_side: u32,
    pub(crate) delta: f32,
    /// A class may take `pcss` where it is certified within the target.
    pub(crate) filter: bool,
    /// The frame-wide grid is taken where it is predicted at most this times the plan's cost.
    pub(crate) fallback: Option<f32>,
    /// The target the plan is decided for; 0: `target`.
    pub(crate) plan_target: f32,
}

impl Regions {
    /// The decision's map side: `centre_size`, or twice the screen's larger side as a power of
    /// two, 64 at least and the scene's shadow_map_size at most. The decision reads penumbra
    /// widths and edges' presence per 16-pixel region, not each pixel's edge: about two texels a
    /// pixel serve it. Every triangle is still rasterized (the map is not culled), so the blocker
    /// search sees every blocker that covers a texel centre of its taps; a blocker thinner than
    /// a texel may fall between centres, as on a map of any size. V comes from the groups' maps.
    pub fn centre_side(&self, width: u32, height: u32, shadow_map_size: u32) -> u32 {
        match self.centre_size {
            0 => (2 * width.max(height))
                .next_power_of_two()
                .clamp(64, shadow_map_size.max(64))
                .min(shadow_map_size),
            s => s,
        }
    }

    /// The target the plan is decided for: `plan_target`, else `target`.
    pub(crate) fn plan_target(&self) -> f32 {
        match self.plan_target {
            t if t > 0.0 => t,
            _ => self.target,
        }
    }

    /// The classes' samples per side: the ladder up to `max_n`, `max_n` last; with `force`, N alone.
    pub(crate) fn ladder(&self) -> Vec<u32> {
        if let Some(n) = self.force {
            return vec![n];
        }
        let mut l: Vec<u32> = LADDER.iter().copied().filter(|&n| n < self.max_n).collect();
        l.push(self.max_n);
        l.truncate(MAX_CLASSES);
        l
    }

    /// How many settings a certified class could end on: the filter, and a centred grid of
    /// every n of the ladder and of its rungs up to `max_n` at every half-octave side from
    /// `min_size` to `max_size` (89 at the defaults). Which setting a class tries next depends on
    /// the bounds of those it tried on the same draws, so the union bound that keeps the chosen
    /// setting's bound at 1 − δ/C runs over all of them: each is bounded at δ/(C · this)
    /// (docs/regions.md, "Certified classes", item 6).
    pub(crate) fn reachable_settings(&self) -> usize {
        let mut n = self.ladder();
        n.extend(LADDER.iter().copied().filter(|&r| r <= self.max_n));
        n.sort_unstable();
        n.dedup();
        let sides = half_octave_sides()
            .filter(|s| (self.min_size..=self.max_size).contains(s))
            .count();
        1 + n.len() * sides
    }
}

impl ShadowMethod for Regions {
    fn unsupported_light(&self, kind: crate::scene::LightKind) -> Option<&'static str> {
        use crate::scene::LightKind;
        (!matches!(kind, LightKind::Rect | LightKind::Disk | LightKind::Spot))
            .then_some(super::ON_A_RECTANGLE)
    }
    fn unsupported_maps(
        &self,
        _kind: crate::scene::LightKind,
        maps: crate::scene::MapKind,
    ) -> Option<&'static str> {
        (maps == crate::scene::MapKind::Hybrid)
            .then_some("its classes' maps are plain arrays of their own sizes (maps = plain)")
    }
    fn name(&self) -> &'static str {
        "regions"
    }
    fn label(&self) -> String {
        super::label_from(
            &INFO,
            &[
                ("target", self.target.to_string()),
                ("density", self.density.to_string()),
                ("max_n", self.max_n.to_string()),
                ("min_size", self.min_size.to_string()),
                ("max_size", self.max_size.to_string()),
                ("region", self.region.to_string()),
                ("blocker_taps", self.blocker_taps.to_string()),
                (
                    "cull",
                    match self.cull {
                        None => "auto",
                        Some(true) => "on",
                        Some(false) => "off",
                    }
                    .to_string(),
                ),
                ("merge", if self.merge { "on" } else { "off" }.to_string()),
                ("map_cost", self.map_cost.to_string()),
                ("sample_cost", self.sample_cost.to_string()),
                (
                    "force",
                    self.force.map_or("off".to_string(), |n| n.to_string()),
                ),
                ("force_size", self.force_size.to_string()),
                ("centre_size", self.centre_size.to_string()),
                ("hold", if self.hold { "on" } else { "off" }.to_string()),
                (
                    "certify",
                    if self.certify { "on" } else { "off" }.to_string(),
                ),
                ("pixels", self.pixels.to_string()),
                ("truth_side", self.truth_side.to_string()),
                ("delta", self.delta.to_string()),
                (
                    "filter",
                    if self.filter { "pcss" } else { "none" }.to_string(),
                ),
                (
                    "fallback",
                    self.fallback.map_or("off".to_string(), |r| r.to_string()),
                ),
                ("plan_target", self.plan_target.to_string()),
            ],
        )
    }
    fn params_json(&self) -> serde_json::Value {
        serde_json::json!({
            "target": self.target, "density": self.density, "max_n": self.max_n, "min_size": self.min_size, "max_size": self.max_size, "region": self.region,
            "blocker_taps": self.blocker_taps, "cull": match self.cull { None => "auto", Some(true) => "on", Some(false) => "off" },
            "merge": self.merge, "map_cost": self.map_cost, "sample_cost": self.sample_cost, "force": self.force, "force_size": self.force_size, "centre_size": self.centre_size, "hold": self.hold,
            "certify": self.certify, "pixels": self.pixels, "truth_side": self.truth_side, "delta": self.delta, "filter": if self.filter { "pcss" } else { "none" }, "fallback": self.fallback, "plan_target": self.plan_target,
        })
    }
    /// Shade binds V whole on each class's tile list (one band). With `force`, the map side and
    /// count are known before the frame: their array is planned (and refused) up front.
    fn size_needs(
        &self,
        scene: &crate::scene::Scene,
        limits: &wgpu::Limits,
    ) -> Vec<crate::gpu::size_plan::SizeNeed> {
        use crate::gpu::size_plan::SizeNeed;
        let mut needs = vec![crate::methods::sizes::visibility(scene, false, limits)];
        if let Some(n) = self.force {
            let r = &scene.render;
            let size = if self.force_size != 0 {
                self.force_size
            } else {
                r.shadow_map_size
            };
            let map_bytes = (size as u64).pow(2) * 4;
            let layers = ((n as u64).pow(2))
                .min(r.shadow_map_budget_mib as u64 * (1 << 20) / map_bytes)
                .min(limits.max_texture_array_layers as u64);
            let forced = match self.force_size {
                0 => format!("regions:force = {n} on shadow_map_size = {size}"),
                _ => format!("regions:force = {n}, force_size = {size}"),
            };
            needs.push(SizeNeed::side("a forced map", size as u64).sized_by(forced.clone()));
            if layers > 0 {
                needs.push(
                    SizeNeed::array(
                        format!("the shadow-map array ({layers} maps of {size}x{size}, {forced})"),
                        layers * map_bytes,
                        layers as u32,
                    )
                    .sized_by(format!(
                        "shadow_map_budget_mib = {}",
                        r.shadow_map_budget_mib
                    )),
                );
            }
        }
        needs
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        if fg.geometry_tiles.bands.len() > 1 {
            return Err(crate::Error::Limit("regions: the frame's V does not fit one binding; its classes' tile lists are one band".into()));
        }
        let ladder = self.ladder();
        let (light_u, light_v) = light_size(fg);
        // The samples get their share of the target; the maps' share sets the density (budget.rs).
        let target = self.plan_target() * budget::SAMPLING_SHARE;
        let mut params = RegionsParams {
            region: self.region,
            ladder_len: ladder.len() as u32,
            max_n: *ladder.last().unwrap_or(&1),
            target,
            blocker_taps: self.blocker_taps,
            max_radius: 32.0,
            light_u,
            light_v,
            ..Default::default()
        };
        params.ladder[..ladder.len()].copy_from_slice(&ladder);
        let centre = self.centre_side(
            fg.gbuffer.width,
            fg.gbuffer.height,
            fg.scene.render.shadow_map_size,
        );
        let probe = CentreMap::sized(fg, centre)?;
        let centre_frame = readback::uniform_buffer(
            fg.ctx,
            "regions centre frame",
            &crate::gpu::structs::GpuFrame {
                map_size: centre,
                ..fg.frame
            },
        );
        let pass = RegionsPass::new(fg.ctx, fg.map_access(), &fg.gbuffer, params)?;
        Ok(Box::new(State {
            method: self.clone(),
            ladder,
            probe,
            centre,
            centre_frame,
            pass,
            frames: HashMap::new(),
            grids: HashMap::new(),
            classes: Vec::new(),
            density: 0.0,
            keep: false,
            reuse: ReuseCounts::default(),
            held: Vec::new(),
            settled: certified::Settled::default(),
            certifying: None,
        }))
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

struct State {
    method: Regions,
    ladder: Vec<u32>,
    probe: CentreMap,
    /// The decision map's side and its frame uniform (rewritten each frame: the camera may move).
    centre: u32,
    centre_frame: wgpu::Buffer,
    pass: RegionsPass,
    /// The frame uniform of each map size.
    frames: HashMap<u32, wgpu::Buffer>,
    /// Each (n, size)'s grid, kept from frame to frame (its samples are refitted every frame).
    grids: HashMap<(u32, u32), Prepared>,
    classes: Vec<ClassRecord>,
    /// This frame's texels per pixel footprint (`State::density`, raised for the maps' share).
    density: f32,
    keep: bool,
    /// This frame's maps rendered and kept.
    reuse: ReuseCounts,
    /// The previous frame's groups, (n, size, window), where `hold` keeps their windows.
    held: Vec<(u32, u32, Bounds)>,
    /// With `hold` and `certify`: the classes' settings the previous frame ended on.
    settled: certified::Settled,
    /// `certify = on`: the truth tracer and the filter, built on the first certified frame.
    certifying: Option<certified::Certifying>,
}

/// A window's side in tangent units as the light's centre sees it: a map's texel_angle at one texel.
fn window_extent(fg: &FrameGpu, window: &Bounds) -> f32 {
    let s = fg.scene;
    sample_view_window(
        &s.light,
        s.emitter.sample_point(&s.light, 0.5, 0.5),
        &s.bounds,
        window,
        1,
        u32::MAX,
    )
    .texel_angle
}

/// A class's box (CLASS_WORDS 2..8) widened by 1% of the scene's diagonal on every side: receivers
/// on the box's face and their lookups' normal offset stay inside the window.
fn widened(words: &[u32], scene: &Bounds) -> Bounds {
    let margin = glam::Vec3::splat(scene.diagonal() * 0.01);
    let min = glam::Vec3::new(
        unordered(words[2]),
        unordered(words[3]),
        unordered(words[4]),
    ) - margin;
    let max = glam::Vec3::new(
        unordered(words[5]),
        unordered(words[6]),
        unordered(words[7]),
    ) + margin;
    Bounds {
        min: min.max(scene.min),
        max: max.min(scene.max),
    }
}

/// `g` with the window of `held`'s group of its (n, size), grown to hold its own receivers, where
/// the grown window's extent stays within the band of its own (`State::held_window`).
fn held_window(held: &[(u32, u32, Bounds)], fg: &FrameGpu, g: &mut Group) {
    let Some((_, _, w)) = held
        .iter()
        .find(|(n, size, _)| (*n, *size) == (g.n, g.size))
    else {
        return;
    };
    let grown = Bounds {
        min: w.min.min(g.window.min),
        max: w.max.max(g.window.max),
    };
    let extent = window_extent(fg, &grown);
    if super::hold::standing(extent as f64, g.extent as f64) != super::hold::Standing::Above {
        g.window = grown;
        g.extent = extent;
    }
}

/// Classes that share one set of maps: the top class's samples per side, the union of their
/// windows, the finest texel any of them needs.
struct Group {
    n: u32,
    classes: Vec<usize>,
    tiles: u32,
    texel_need: f32,
    window: Bounds,
    size: u32,
    extent: f32,
}

/// Every side `half_octave` gives, ascending and distinct: 2^(k/2) to a multiple of 16, up to
/// 8192.
pub(crate) fn half_octave_sides() -> impl Iterator<Item = u32> {
    (0..=26u32)
        .map(|k| (2f32.powf(k as f32 / 2.0).round() as u32).div_ceil(16) * 16)
        .scan(0, |last, s| {
            let new = s > *last;
            *last = s;
            Some(new.then_some(s))
        })
        .flatten()
}

/// The least side of the form 2^(k/2), rounded up to a multiple of 16, at or above `want`
/// (1 where `want` is not a finite positive number: min_size then sets it).
pub fn half_octave(want: f32) -> u32 {
    if !(want.is_finite() && want >= 1.0) {
        return 1;
    }
    let k = (2.0 * want.min(8192.0).log2()).ceil();
    let side = 2f32.powf(k / 2.0).round() as u32;
    side.div_ceil(16) * 16
}

/// Texels per pixel footprint at least: the `density` parameter where set, else 1 + the lookup's
/// offsets in texels (what a texel must leave after the bias moves the lookup).
pub fn density_floor(density: f32, bias: &crate::scene::BiasDef) -> f32 {
    if density > 0.0 {
        density
    } else {
        1.0 + bias.constant + bias.slope + bias.normal_offset
    }
}

impl State {
    fn density_floor(&self, fg: &FrameGpu) -> f32 {
        density_floor(self.method.density, &fg.scene.render.bias)
    }

    /// The class's maps: samples fitted to `window`, `size` texels a side.
    fn samples(&self, fg: &FrameGpu, n: u32, window: &Bounds, size: u32) -> Vec<GpuSample> {
        let s = fg.scene;
        regular_points(n, Layout::Centred)
            .into_iter()
            .map(|(u, v)| {
                sample_view_window(
                    &s.light,
                    s.emitter.sample_point(&s.light, u, v),
                    &s.bounds,
                    window,
                    size,
                    u32::MAX,
                )
            })
            .collect()
    }

    /// `group` with its map side: the window's extent over the texel it needs, times the density,
    /// rounded up to a half octave (steps of √2, so at most 2× the texels asked for, not 4×), a
    /// multiple of 16, within min_size..=max_size. With `force`, force_size or the scene's.
    fn sized(&self, fg: &FrameGpu, mut group: Group) -> Group {
        let s = fg.scene;
        group.extent = window_extent(fg, &group.window);
        group.size = match self.method.force {
            Some(_) if self.method.force_size != 0 => self.method.force_size,
            Some(_) => s.render.shadow_map_size,
            None => half_octave((group.extent * self.density / group.texel_need).ceil())
                .clamp(self.method.min_size, self.method.max_size),
        };
        group
    }

    /// A group's predicted frame cost in texel equivalents (docs/regions.md, "Groups"): each of
    /// its n² maps costs `map_cost` + its texels, and shades its tiles' pixels at `sample_cost` each.
    fn cost(&self, g: &Group) -> f64 {
        let pixels = g.tiles as f64 * 64.0;
        (g.n as f64).powi(2)
            * (self.method.map_cost as f64
                + (g.size as f64).powi(2)
                + self.method.sample_cost as f64 * pixels)
    }

    /// Greedy, from the fewest samples up: a group joins the next one (more samples, the union of
    /// the windows, the finer texel) when the joined group is predicted cheaper than the two. Its
    /// tiles only gain samples, so the frame's sampling error only falls. All joined: one group,
    /// the culled grid of the top n.
    fn merged(&self, fg: &FrameGpu, mut groups: Vec<Group>) -> Vec<Group> {
        let mut i = 0;
        while i + 1 < groups.len() {
            let (a, b) = (&groups[i], &groups[i + 1]);
            let window = Bounds {
                min: a.window.min.min(b.window.min),
                max: a.window.max.max(b.window.max),
            };
            let classes = a.classes.iter().chain(&b.classes).copied().collect();
            let joined = self.sized(
                fg,
                Group {
                    n: b.n,
                    classes,
                    tiles: a.tiles + b.tiles,
                    texel_need: a.texel_need.min(b.texel_need),
                    window,
                    size: 0,
                    extent: 0.0,
                },
            );
            if self.cost(&joined) < self.cost(a) + self.cost(b) {
                groups.splice(i..i + 2, [joined]);
            } else {
                i += 1;
            }
        }
        groups
    }

    /// `hold`: a group with the previous frame's samples per side and map size keeps that frame's
    /// window, grown to hold its own receivers, while the grown window's extent stays within the
    /// band (`hold::standing`) of its own window's: the texel it gives is then at most that much
    /// coarser than the one it asked for. An unchanged window keeps its maps (their keys).
    fn held_window(&self, fg: &FrameGpu, g: &mut Group) {
        held_window(&self.held, fg, g);
    }

    fn grid(&mut self, fg: &FrameGpu, n: u32, size: u32) -> Result<&mut Prepared> {
        self.frames.entry(size).or_insert_with(|| {
            readback::uniform_buffer(
                fg.ctx,
                "regions frame",
                &crate::gpu::structs::GpuFrame {
                    map_size: size,
                    ..fg.frame
                },
            )
        });
        if !self.grids.contains_key(&(n, size)) {
            let frame =
                (size != fg.scene.render.shadow_map_size).then(|| self.frames[&size].clone());
            // Each (n, size)'s maps are kept from frame to frame (docs/reuse.md); a map is used
            // again where its window is unchanged (its key), and culled maps are never kept.
            let mut grid = fixed_samples::prepare_kept(
                fg,
                &regular_points(n, Layout::Centred),
                size,
                frame,
                Some(&format!("regions {n}x{size}")),
            )?;
            if self.method.cull != Some(false) {
                match grid.cull(fg) {
                    // auto on a device that cannot cull: the uncut maps, the same V.
                    Err(crate::Error::Limit(_)) if self.method.cull.is_none() => {}
                    r => r?,
                }
            }
            self.grids.insert((n, size), grid);
        }
        Ok(self.grids.get_mut(&(n, size)).expect("inserted above"))
    }
}

impl MethodState for State {
    fn reset(&mut self, _fg: &FrameGpu) -> Result<()> {
        self.reuse = ReuseCounts::default();
        Ok(())
    }
    fn keep_intermediates(&mut self) {
        self.keep = true;
    }
    /// The groups' maps, and the decision's centre map (rendered every frame).
    fn reuse(&self) -> Option<ReuseCounts> {
        Some(self.reuse)
    }
    fn release_maps(&mut self) -> Vec<crate::render::kept_maps::KeptMaps> {
        self.grids
            .values_mut()
            .filter_map(Prepared::release)
            .collect()
    }
    /// With `hold`, the groups' windows and the certified classes' settings: the next frame's
    /// state starts from them.
    fn memory(&self) -> Option<serde_json::Value> {
        let windows: Vec<serde_json::Value> = self
            .held
            .iter()
            .map(|(n, size, w)| serde_json::json!([n, size, w.min.to_array(), w.max.to_array()]))
            .collect();
        (self.method.hold && !(windows.is_empty() && self.settled.is_empty()))
            .then(|| serde_json::json!({"windows": windows, "settled": self.settled.to_json()}))
    }
    fn recall(&mut self, memory: &serde_json::Value) {
        let v3 = |v: &serde_json::Value| -> Option<glam::Vec3> {
            Some(glam::Vec3::new(
                v[0].as_f64()? as f32,
                v[1].as_f64()? as f32,
                v[2].as_f64()? as f32,
            ))
        };
        self.held = memory["windows"]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(|g| {
                Some((
                    g[0].as_u64()? as u32,
                    g[1].as_u64()? as u32,
                    Bounds {
                        min: v3(&g[2])?,
                        max: v3(&g[3])?,
                    },
                ))
            })
            .collect();
        self.settled = certified::Settled::from_json(&memory["settled"]);
    }
    fn run(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        pictures: bool,
    ) -> Result<MethodOutput> {
        let ctx = fg.ctx;
        ctx.queue.write_buffer(
            &self.centre_frame,
            0,
            bytemuck::bytes_of(&crate::gpu::structs::GpuFrame {
                map_size: self.centre,
                ..fg.frame
            }),
        );
        self.probe.render(fg, timer)?;
        timer.stage(ctx, Stage::REGIONS, |enc| {
            self.pass.record(
                ctx,
                enc,
                &RegionsInputs {
                    frame: &self.centre_frame,
                    gbuffer: &fg.gbuffer,
                    tiles: &fg.geometry_tiles,
                    samples: &self.probe.samples,
                    maps: self.probe.view(),
                },
            );
            Ok(())
        })?;
        // The one read-back of the decision: per class its tiles, finest texel and receiver box.
        timer.flush(ctx);
        let classes = self.ladder.len();
        let region_bytes = self.pass.region_count as u64 * REGION_WORDS as u64 * 4;
        let (words, regions): (Vec<u32>, Vec<u32>) = timer.cpu(Stage::READBACK, || {
            // Both copies in one submission: one wait (the second map finds the copy done).
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            let class_staging = readback::stage_copy(
                ctx,
                &mut enc,
                &self.pass.classes,
                (classes * CLASS_WORDS * 4) as u64,
            );
            let region_staging =
                readback::stage_copy(ctx, &mut enc, &self.pass.regions, region_bytes);
            ctx.queue.submit([enc.finish()]);
            Ok((
                readback::map_staging(ctx, &class_staging)?,
                readback::map_staging(ctx, &region_staging)?,
            ))
        })?;
        let syncs = 1 + self.probe.syncs();
        // The maps' share of the target: the density whose predicted maps' error meets it.
        let (edges, pixels) = budget::edge_weight(&self.pass.params, &regions);
        let floor = self.density_floor(fg) as f64;
        self.density = match self.method.density {
            d if d > 0.0 => d,
            _ => budget::map_density(edges, pixels, self.method.plan_target() as f64, floor) as f32,
        };
        let s = fg.scene;
        let mut groups: Vec<Group> = Vec::new();
        for c in 0..classes {
            let w = &words[c * CLASS_WORDS..(c + 1) * CLASS_WORDS];
            if w[0] == 0 {
                continue;
            }
            let window = match self.method.force {
                Some(_) => s.bounds,
                None => widened(w, &s.bounds),
            };
            let group = Group {
                n: self.ladder[c],
                classes: vec![c],
                tiles: w[0],
                texel_need: texel_need(w),
                window,
                size: 0,
                extent: 0.0,
            };
            groups.push(self.sized(fg, group));
        }
        let mut record = RegionsRecord {
            region: self.method.region,
            ladder: self.ladder.clone(),
            decision_maps: self.probe.count(),
            centre_size: self.centre,
            density: self.density,
            predicted_map: budget::predicted_map(edges, pixels, self.density as f64),
            classes: Vec::new(),
            triangle_map_pairs: None,
            texels_written: None,
            target: None,
            target_met: None,
            certified: None,
        };
        let (maps, syncs) = if self.method.certify && self.method.force.is_none() {
            let (maps, more) = self.certified_frame(fg, timer, &words, groups, &mut record)?;
            (maps, syncs + more)
        } else {
            if self.method.force.is_none() && self.method.merge {
                groups = self.merged(fg, groups);
            }
            self.hold_windows(fg, &mut groups);
            let (maps, more) = self.render_groups(fg, timer, &groups, &words, &mut record)?;
            (maps, syncs + more)
        };
        self.reuse
            .add(&ReuseCounts::all_rendered(self.probe.count(), self.centre));
        let pictures = if pictures {
            pictures::pictures(fg, &self.pass, &self.classes)?
        } else {
            Vec::new()
        };
        Ok(MethodOutput {
            shadow_maps: maps + self.probe.count(),
            syncs,
            record: super::record_value("regions", &record)?,
            pictures,
            bound: None,
        })
    }
    /// [`RegionsBuffers`]: the centre map, the decision's buffers, and each class's shade inputs.
    fn inspect(&mut self, fg: &FrameGpu) -> Result<Option<Box<dyn std::any::Any>>> {
        let ctx = fg.ctx;
        let p = &self.pass;
        let tiles_words = (p.params.ladder_len * p.params.section_words) as u64 * 4;
        let geometry: Vec<u32> =
            readback::read_buffer(ctx, &fg.geometry_tiles.list, fg.geometry_tiles.bytes)?;
        let count = geometry[0] as usize;
        let mut geometry_tiles = geometry[crate::stages::shade::TILE_LIST_HEADER
            ..crate::stages::shade::TILE_LIST_HEADER + count]
            .to_vec();
        geometry_tiles.sort_unstable();
        let out = RegionsBuffers {
            params: p.params,
            centre_size: self.centre,
            sample: self.probe.sample,
            map: self.probe.read(fg)?,
            regions: readback::read_buffer(
                ctx,
                &p.regions,
                p.region_count as u64 * REGION_WORDS as u64 * 4,
            )?,
            classes: readback::read_buffer(
                ctx,
                &p.classes,
                p.params.ladder_len as u64 * CLASS_WORDS as u64 * 4,
            )?,
            totals: readback::read_buffer::<u32>(ctx, &p.totals, 8)?
                .try_into()
                .expect("two words"),
            class_tiles: readback::read_buffer(ctx, &p.class_tiles, tiles_words)?,
            group_tiles: readback::read_buffer(ctx, &p.group_tiles, tiles_words)?,
            geometry_tiles,
            records: self.classes.clone(),
        };
        Ok(Some(Box::new(out)))
    }
}

/// What a frame's decision read and wrote, for the twins.
pub struct RegionsBuffers {
    pub params: RegionsParams,
    /// The decision map's side (the frame uniform's map_size for `measure`).
    pub centre_size: u32,
    pub sample: GpuSample,
    pub map: Vec<f32>,
    pub regions: Vec<u32>,
    pub classes: Vec<u32>,
    pub totals: [u32; 2],
    /// A section of `params.section_words` per class: header, then tiles in the GPU's order.
    pub(crate) class_tiles: Vec<u32>,
    /// The same per group of two classes or more (`RegionsPass::join`); a group of one shades
    /// its class's own section.
    pub(crate) group_tiles: Vec<u32>,
    /// The frame's geometry tiles, sorted.
    pub geometry_tiles: Vec<u32>,
    pub records: Vec<ClassRecord>,
}

impl RegionsBuffers {
    /// Class `c`'s tiles, sorted.
    pub fn class_list(&self, c: usize) -> Vec<u32> {
        section(&self.class_tiles, c, self.params.section_words as usize)
    }

    /// Group `g`'s joined tiles, sorted.
    pub fn group_list(&self, g: usize) -> Vec<u32> {
        section(&self.group_tiles, g, self.params.section_words as usize)
    }
}

/// Section `k` of a buffer of tile lists, sorted.
fn section(words: &[u32], k: usize, section_words: usize) -> Vec<u32> {
    let base = k * section_words;
    let count = words[base] as usize;
    let start = base + crate::stages::shade::TILE_LIST_HEADER;
    let mut l = words[start..start + count].to_vec();
    l.sort_unstable();
    l
}

/// A class's finest texel need (CLASS_WORDS 1), infinite where none of its pixels asked.
fn texel_need(words: &[u32]) -> f32 {
    if words[1] == u32::MAX {
        f32::INFINITY
    } else {
        unordered(words[1])
    }
}

impl State {
    /// `hold`: each group keeps the previous frame's window where it holds (`held_window`).
    fn hold_windows(&mut self, fg: &FrameGpu, groups: &mut [Group]) {
        if self.method.hold && self.method.force.is_none() {
            for g in groups.iter_mut() {
                self.held_window(fg, g);
            }
            self.held = groups.iter().map(|g| (g.n, g.size, g.window)).collect();
        }
    }

    /// Group `g`'s maps rendered and shaded into V on its tiles (V accumulates: each tile is shaded
    /// by one group between clears).
    fn render_group(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        g: usize,
        group: &Group,
        words: &[u32],
    ) -> Result<MethodOutput> {
        let ctx = fg.ctx;
        let (n, size, window) = (group.n, group.size, group.window);
        let samples = self
            .method
            .force
            .is_none()
            .then(|| self.samples(fg, n, &window, size));
        // One class: its own list. Several: their lists joined into one (one shade pass per block).
        let tiles = if let [c] = group.classes[..] {
            self.pass.class_list(c as u32, fg.gbuffer.height)
        } else {
            let counts: Vec<(u32, u32)> = group
                .classes
                .iter()
                .map(|&c| (c as u32, words[c * CLASS_WORDS]))
                .collect();
            let mut joined = None;
            timer.stage(ctx, Stage::REGIONS, |enc| {
                joined = Some(
                    self.pass
                        .join(ctx, enc, g as u32, &counts, fg.gbuffer.height),
                );
                Ok(())
            })?;
            joined.expect("recorded above")
        };
        let keep = self.keep;
        let grid = self.grid(fg, n, size)?;
        if let Some(samples) = samples {
            grid.set_samples(ctx, samples);
        }
        grid.set_tiles(tiles);
        if keep {
            grid.keep_intermediates();
        }
        let out = grid.run(fg, timer, false)?;
        let counts = grid.reuse_counts().unwrap_or_default();
        self.reuse.add(&counts);
        Ok(out)
    }

    /// The class records of group `g` as rendered (`out`: its grid's output).
    fn class_records(
        g: usize,
        group: &Group,
        words: &[u32],
        ladder: &[u32],
        out: &MethodOutput,
    ) -> Vec<ClassRecord> {
        let tris = out.record["triangles_per_map_mean"].as_f64().unwrap_or(0.0);
        group
            .classes
            .iter()
            .map(|&c| {
                let w = &words[c * CLASS_WORDS..(c + 1) * CLASS_WORDS];
                ClassRecord {
                    class: c as u32,
                    decided_n: ladder[c],
                    group: g as u32,
                    n: group.n,
                    map_size: group.size,
                    tiles: w[0],
                    maps: out.shadow_maps,
                    texel_need: texel_need(w),
                    extent: group.extent,
                    triangles_per_map_mean: tris,
                }
            })
            .collect()
    }

    /// Every group rendered into V; the record gains the classes and the maps' totals. Returns
    /// the maps rendered and the grids' syncs.
    fn render_groups(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        groups: &[Group],
        words: &[u32],
        record: &mut RegionsRecord,
    ) -> Result<(u32, u32)> {
        let (mut maps, mut syncs) = (0u32, 0u32);
        let (mut pairs, mut texels) = (0f64, 0f64);
        let mut records = Vec::new();
        for (g, group) in groups.iter().enumerate() {
            let out = self.render_group(fg, timer, g, group, words)?;
            syncs += out.syncs;
            maps += out.shadow_maps;
            let tris = out.record["triangles_per_map_mean"].as_f64().unwrap_or(0.0);
            pairs += tris * out.shadow_maps as f64;
            texels += out.shadow_maps as f64 * (group.size as f64).powi(2);
            records.extend(Self::class_records(g, group, words, &self.ladder, &out));
        }
        record.classes = records.clone();
        record.triangle_map_pairs = Some(pairs);
        record.texels_written = Some(texels);
        self.classes = records;
        Ok((maps, syncs))
    }
}
