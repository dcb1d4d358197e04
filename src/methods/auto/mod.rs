//! auto: an error budget (docs/error-estimate.md §6). Frame by frame it chooses the sample count
//! and the map size of the centred grid whose predicted RMSE of V (the calibrated estimate, no
//! reference) meets `target`, among the grids the calibration was fitted on (odd sides, even ones
//! to 6, maps of 512² and up: `sides`, `sizes`): it renders the current choice with the estimate, and while the prediction
//! misses the target it moves to the cheapest grid that the prediction says meets it (more
//! samples lower the sampling error and the part of the maps' error that averages over samples;
//! larger maps lower all of the maps' error). The state's first search also steps down from a try
//! that meets the target to a cheaper grid predicted to meet it. The choice carries over to the
//! next frame and from there only rises, so a sequence's decisions do not flicker. Once a frame
//! has settled the choice (its prediction met the target, or nothing could grow), the state's
//! later frames have the same inputs until the camera moves, so they render the chosen grid
//! without the estimate. A grid that meets the target also judges one-map methods
//! (`filter`): one predicted to meet it is rendered instead.

use super::{
    check_range, get_choice, get_f32, get_u32, Family, MethodInfo, MethodOutput, MethodState,
    Param, ParamMap, ShadowMethod,
};
use crate::gpu::timing::StageTimer;
use crate::methods::calibration::{self, Class};
use crate::methods::estimate::Prediction;
use crate::methods::fixed_samples::{self, regular_points, Layout, Prepared};
use crate::render::kept_maps::ReuseCounts;
use crate::stages::FrameGpu;
use crate::Result;
use filter::{Candidates, Met, Reference};
use std::collections::BTreeMap;

mod certified;
pub mod filter;
pub mod price;

pub const INFO: MethodInfo = MethodInfo {
    name: "auto",
    family: Family::MultiSample,
    summary: "error budget: the centred grid's n and map size grown until the predicted RMSE of V meets the target (or one filtered map, where it is predicted to), then kept while the camera stays",
    params: &[
        Param { key: "target", default: "0.015", help: "RMSE of V to reach, 0.0005..=0.5 (predicted without a reference; docs/error-estimate.md)" },
        Param { key: "max_n", default: "17", help: "largest grid side it may choose, 2..=32" },
        Param { key: "max_size", default: "2048", help: "largest map size it may choose: 256, 512, 1024 or 2048" },
        Param { key: "cost", default: "measured", help: "how it prices a map of each size: `measured` (what a map of each size adds to this scene's frame on this device, timed before the clock, once per process) or `texels` (double per doubling of the side: the same choice on every device)" },
        Param { key: "filters", default: "pcss+msm", help: "one-map methods checked against the grid that meets the target (or, out of reach, the best grid tried), joined by + (e.g. pcss, or pcss+msm+vsm), or none: one predicted to meet it (out of reach: to err no more than that grid) that took less time is rendered instead; the default leaves out those that refuse the scene's light" },
        Param { key: "pixels", default: "2048", help: "K: pixels whose exact truth certifies the choice (docs/certify.md): the cheapest candidate whose bound on its RMSE is at most the target is rendered; 0 decides by the estimate alone" },
        Param { key: "delta", default: "0.05", help: "each candidate's bound holds with probability 1 − delta, in (0, 1)" },
    ],
    parse: |p: &ParamMap| {
        let target = check_range("auto", "target", get_f32(p, "target", 0.015)?, 0.0005, 0.5)?;
        let max_n = check_range("auto", "max_n", get_u32(p, "max_n", 17)?, 2, 32)?;
        let max_size = get_u32(p, "max_size", 2048)?;
        if !SIZES.contains(&max_size) {
            return Err(crate::Error::Param(format!("auto: max_size = {max_size}: use one of 256, 512, 1024, 2048")));
        }
        let cost = match get_choice(p, "cost", "measured", &["measured", "texels"])? {
            "texels" => CostModel::Texels,
            _ => CostModel::Measured,
        };
        let filters = p.get("filters").map_or(DEFAULT_FILTERS, String::as_str).to_string();
        filter::parse_list(&filters)?;
        let pixels = check_range("auto", "pixels", get_u32(p, "pixels", DEFAULT_PIXELS)?, 0, 1 << 20)?;
        let delta = get_f32(p, "delta", 0.05)?;
        if !(delta > 0.0 && delta < 1.0) {
            return Err(crate::Error::Param(format!("auto: delta = {delta} is outside (0, 1): each bound holds with probability 1 − delta")));
        }
        Ok(std::sync::Arc::new(Auto { target, max_n, max_size, cost, filters, pixels, delta }))
    },
};

/// The one-map candidates unless `filters` says otherwise: `pcss` for the soft edges of small
/// scenes, `msm` for the acne-prone ones (`grazing-ground`: 0.126 against the grid's 0.189).
pub const DEFAULT_FILTERS: &str = "pcss+msm";
/// K: the exact pixels a decision draws (`certified`).
pub const DEFAULT_PIXELS: u32 = 2048;

/// The map sizes it steps through.
pub const SIZES: [u32; 4] = [256, 512, 1024, 2048];
/// The grid sides it chooses from, 2 to `max_n`: those the calibration was fitted on
/// (`calibration::fitted_side`: the odd ones, the even ones to 6 with their own sampling factor).
pub fn sides(max_n: u32) -> Vec<u32> {
    (2..=max_n)
        .filter(|&n| calibration::fitted_side(n))
        .collect()
}

/// The map sizes it chooses from: 512² (`calibration::MIN_FITTED_SIZE`) to `max_size` (256²
/// alone where `max_size` is 256).
pub fn sizes(max_size: u32) -> Vec<u32> {
    let fitted: Vec<u32> = SIZES
        .iter()
        .copied()
        .filter(|&z| z >= calibration::MIN_FITTED_SIZE && z <= max_size)
        .collect();
    if fitted.is_empty() {
        vec![max_size]
    } else {
        fitted
    }
}

/// The first frame's choice: the smallest grid with half sets in both axes at 512² maps.
const START: (u32, u32) = (3, 512);
/// At most this many tries in one frame (each a full render of a grid).
const MAX_TRIES: usize = 8;
/// Sampling error falls about as n^-1.5 on the scenes measured (docs/error-estimate.md §6).
pub const SAMPLING_ORDER: f64 = 1.5;
/// A choice handed on from the previous frame of a sequence is kept while its prediction is
/// within this factor of the target: the prediction moves from frame to frame as the light moves,
/// and a choice that only rises would otherwise ratchet up on that noise
/// (docs/error-estimate.md §6). It is the band of `hold` (docs/reuse.md §3).
const KEEP: f64 = super::hold::BAND;
/// The grid a filter is judged against is predicted to err by at most this share of the target,
/// so that its own error, taken out of the difference, cannot hide a filter's (docs/error-estimate.md §6).
const REFERENCE: f64 = 0.5;
/// A filter read against the grid that met the target at more than this many times the target is
/// not worth the reference (docs/error-estimate.md §6).
const SCREEN: f64 = 1.5;

#[derive(Clone, Debug, PartialEq)]
pub struct Auto {
    pub target: f32,
    pub max_n: u32,
    pub max_size: u32,
    pub cost: CostModel,
    /// `none`, or one-map methods joined by `+` (filter::parse_list).
    pub filters: String,
    /// K, the exact pixels that certify the choice; 0: the estimate alone decides.
    pub pixels: u32,
    pub delta: f32,
}

/// How a map of each size is priced in the search (docs/error-estimate.md §6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CostModel {
    /// What a map of each size adds to this scene's frame on this device (`price`).
    Measured,
    /// Double per doubling of the side, on every device.
    Texels,
}

impl CostModel {
    fn name(self) -> &'static str {
        match self {
            CostModel::Measured => "measured",
            CostModel::Texels => "texels",
        }
    }
}

impl ShadowMethod for Auto {
    fn name(&self) -> &'static str {
        "auto"
    }
    fn label(&self) -> String {
        super::label_from(
            &INFO,
            &[
                ("target", format!("{}", self.target)),
                ("max_n", self.max_n.to_string()),
                ("max_size", self.max_size.to_string()),
                ("cost", self.cost.name().to_string()),
                ("filters", self.filters.clone()),
                ("pixels", self.pixels.to_string()),
                ("delta", format!("{}", self.delta)),
            ],
        )
    }
    fn params_json(&self) -> serde_json::Value {
        serde_json::json!({ "target": self.target, "max_n": self.max_n, "max_size": self.max_size, "cost": self.cost.name(), "filters": self.filters, "pixels": self.pixels, "delta": self.delta })
    }
    fn unsupported_light(&self, kind: crate::scene::LightKind) -> Option<&'static str> {
        (!(super::maps_from_the_emitter(kind) || super::cube_maps(kind)))
            .then_some(super::ON_A_RECTANGLE)
    }
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        if fg.scene.render.maps == crate::scene::MapKind::Hybrid {
            return Err(crate::Error::Param(
                "auto: it chooses plain map sizes itself; it cannot run with maps = hybrid".into(),
            ));
        }
        crate::stages::estimate::check_bands(
            &fg.geometry_tiles,
            fg.gbuffer.width,
            fg.gbuffer.height,
        )?;
        let start = (START.0.min(self.max_n), START.1.min(self.max_size));
        let (costs, pricing_ms) = map_costs(fg, self.cost, self.max_size)?;
        // Candidates that refuse the light: an error where the list was given, left out (and
        // recorded) from the default one.
        let (mut kept, mut left_out) = (Vec::new(), Vec::new());
        for m in filter::parse_list(&self.filters)? {
            match m.check_light(fg.scene) {
                Ok(()) => kept.push(m),
                Err(_) if self.filters == DEFAULT_FILTERS => left_out.push(m.label()),
                Err(e) => {
                    return Err(crate::Error::Param(format!(
                        "auto: filters = {}: {e}",
                        self.filters
                    )))
                }
            }
        }
        let filters = Candidates::new(kept, left_out);
        // The scene's truth tracer (its BVH), built once before the clock, as the prices are.
        let certifying = (self.pixels > 0)
            .then(|| certified::Certifying::new(fg, self.pixels as usize, self.delta as f64))
            .transpose()?;
        Ok(Box::new(AutoState {
            method: self.clone(),
            choice: start,
            grid: None,
            frames: BTreeMap::new(),
            warned: false,
            settled: None,
            recalled: false,
            costs,
            pricing_ms,
            searched: false,
            filters,
            filter: None,
            handed_filter: None,
            class: Class::of(fg.scene.emitter.kind()),
            certifying,
            reuse: ReuseCounts::default(),
        }))
    }
    fn size_needs(
        &self,
        scene: &crate::scene::Scene,
        limits: &wgpu::Limits,
    ) -> Vec<crate::gpu::size_plan::SizeNeed> {
        vec![crate::methods::sizes::visibility(scene, true, limits)]
    }
    fn times_frames_at_build(&self) -> bool {
        self.cost == CostModel::Measured
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// One try of a frame: the grid, its maps and the prediction.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct Try {
    pub n: u32,
    pub map_size: u32,
    pub maps: u32,
    /// Wall clock from the first map to the estimate read back, ms.
    pub ms: f64,
    /// The calibrated prediction (`calibration::calibrated`), what the search reads.
    #[serde(flatten)]
    pub prediction: Prediction,
    /// The estimate's own predicted RMSE before the calibration's factors.
    pub predicted_raw: f64,
}

pub struct AutoState {
    method: Auto,
    /// The grid the next frame starts with.
    choice: (u32, u32),
    /// The grid last tried: one at a time, as each may hold the whole map budget.
    grid: Option<((u32, u32), Prepared)>,
    /// The frame uniform of each map size.
    frames: BTreeMap<u32, wgpu::Buffer>,
    warned: bool,
    /// The frame that settled `choice`: its record and bound. Later frames of this state (same
    /// scene, light and camera) would predict the same, so they render the grid alone.
    settled: Option<(serde_json::Value, Vec<f32>)>,
    /// The choice came from the previous frame of a sequence (`recall`): its first try is kept
    /// within KEEP of the target.
    recalled: bool,
    /// The price of one map of each size.
    costs: Costs,
    /// The wall time the pricing took before the clock (0 where the process had priced the scene).
    pricing_ms: f64,
    /// A frame has searched: only the state's first search steps down (a later one, after the
    /// camera moved or handed on in a sequence, only rises, so decisions do not flicker).
    searched: bool,
    /// The one-map methods checked against the grid that met the target (`filter`).
    filters: Candidates,
    /// The candidate the settling frame chose: the settled frames render it instead of the grid.
    filter: Option<usize>,
    /// The filter the previous frame of a sequence chose (`recall`), kept within KEEP.
    handed_filter: Option<String>,
    /// The scene's class for the calibrated estimate (from its light).
    class: Class,
    /// `pixels` > 0: the exact truth that certifies the choice (`certified`).
    certifying: Option<certified::Certifying>,
    /// This frame's maps rendered and kept, over its tries.
    reuse: ReuseCounts,
}

/// The price of one map of each size the search may choose (ms under `measured`, relative under
/// `texels`), in SIZES order.
#[derive(Clone, Debug, PartialEq)]
pub struct Costs(pub Vec<(u32, f64)>);

impl Costs {
    /// Double per doubling of the side. From 512² to 1024² maps a map costs 1.1–1.3× more on the
    /// meshes and 1.6–2.9× on the small analytic scenes on lavapipe (docs/error-estimate.md §6).
    pub fn texels(max_size: u32) -> Costs {
        Costs(
            sizes(max_size)
                .into_iter()
                .map(|z| (z, z as f64 / 512.0))
                .collect(),
        )
    }
    fn of(&self, size: u32) -> f64 {
        self.0
            .iter()
            .find(|(z, _)| *z == size)
            .map_or(f64::INFINITY, |(_, c)| *c)
    }
}

/// Each size's price under `model`, and the wall time the pricing took: `measured` times this
/// scene's frames at each size before the clock, once per process and scene (`price`).
fn map_costs(fg: &FrameGpu, model: CostModel, max_size: u32) -> Result<(Costs, f64)> {
    match model {
        CostModel::Texels => Ok((Costs::texels(max_size), 0.0)),
        CostModel::Measured => {
            price::measured(fg, &sizes(max_size)).map(|(priced, ms)| (Costs(priced), ms))
        }
    }
}

/// The calibrated sampling error of side n2 from side n's, in a scene of `class`: it falls as
/// n^−1.5, and an even side and an odd one take their own factors (`calibration::factors_at`).
fn sampling_at(class: Class, n: u32, sampling: f64, n2: u32) -> f64 {
    let factor =
        calibration::factors_at(class, n2).sampling / calibration::factors_at(class, n).sampling;
    sampling * (n as f64 / n2 as f64).powf(SAMPLING_ORDER) * factor
}

/// The predicted RMSE of the centred grid (n2, size2), from a try at (n, size) in a scene of
/// `class`: the sampling error falls as n^−1.5 (`sampling_at`); of the maps' error, the part
/// that averages over samples falls as 1/n (`Prediction::predicted_map_averaging`), and all of it
/// at best as the texel size.
pub fn predicted_at(class: Class, n: u32, size: u32, p: &Prediction, n2: u32, size2: u32) -> f64 {
    let s = sampling_at(class, n, p.predicted_sampling, n2);
    // Fewer samples or smaller maps (a step down) raise both parts by the same laws.
    let kept = 1.0 - (n * n) as f64 / (n2 * n2) as f64;
    let texel = size as f64 / size2 as f64;
    let m2 = (p.predicted_map.powi(2) - p.predicted_map_averaging.powi(2) * kept).max(0.0)
        * texel
        * texel;
    (s * s + m2).sqrt()
}

/// A step down: the cheapest grid not yet `tried`, cheaper than (n, size), of `sides(max_n)` and
/// `sizes(max_size)`, that `predicted_at` says meets `target` too; None if none does.
#[allow(clippy::too_many_arguments)] // the search's state, passed whole; a search type would hold it
pub fn cheaper_meeting(
    class: Class,
    n: u32,
    size: u32,
    p: &Prediction,
    target: f64,
    max_n: u32,
    max_size: u32,
    costs: &Costs,
    tried: &[(u32, u32)],
) -> Option<(u32, u32)> {
    let here = (n * n) as f64 * costs.of(size);
    let mut best: Option<(f64, (u32, u32))> = None;
    for size2 in sizes(max_size) {
        for n2 in sides(max_n) {
            let cost = (n2 * n2) as f64 * costs.of(size2);
            if cost >= here {
                break;
            }
            if !tried.contains(&(n2, size2))
                && predicted_at(class, n, size, p, n2, size2) <= target
                && best.is_none_or(|(c, _)| cost < c)
            {
                best = Some((cost, (n2, size2)));
            }
        }
    }
    best.map(|(_, choice)| choice)
}

/// The cheapest grid (its maps at `costs`' price) of `sides` at n ≥ `n` and `sizes` at maps ≥ `size`, other than
/// (n, size), that `predicted_at` says meets `target`; None if none does.
#[allow(clippy::too_many_arguments)] // the search's state, passed whole; a search type would hold it
fn cheapest_meeting(
    class: Class,
    n: u32,
    size: u32,
    p: &Prediction,
    target: f64,
    max_n: u32,
    max_size: u32,
    costs: &Costs,
) -> Option<(u32, u32)> {
    let mut best: Option<(f64, (u32, u32))> = None;
    for size2 in sizes(max_size).into_iter().filter(|&z| z >= size) {
        // At one size the cost rises with n: the first n that meets it is that size's cheapest.
        let meets = sides(max_n)
            .into_iter()
            .filter(|&n2| n2 >= n && (n2, size2) != (n, size))
            .find(|&n2| predicted_at(class, n, size, p, n2, size2) <= target);
        if let Some(n2) = meets {
            let cost = (n2 * n2) as f64 * costs.of(size2);
            if best.is_none_or(|(c, _)| cost < c) {
                best = Some((cost, (n2, size2)));
            }
        }
    }
    best.map(|(_, choice)| choice)
}

/// The next grid after a try that missed `target`, or None when nothing that can grow would
/// reach it. First the cheapest grid predicted to meet it (`cheapest_meeting`). Where none is,
/// the target is out of reach by the prediction, and shares decide what grows: the maps' error
/// gets half the target's square while the map size can double; the sampling error gets the
/// rest, and n grows to what its order says reaches that (at least one more). Where n is at its
/// largest the maps take the excess; where the maps are at their largest and their error alone
/// misses the target, nothing can reach it. Where even the largest maps would miss it (their
/// error falling at best as the texel size), the sampling error need only stay under half that
/// floor, which adds at most 12% to it: n does not chase a target the maps put out of reach.
#[allow(clippy::too_many_arguments)] // the search's state, passed whole; a search type would hold it
pub fn next_choice(
    class: Class,
    n: u32,
    size: u32,
    p: &Prediction,
    target: f64,
    max_n: u32,
    max_size: u32,
    costs: &Costs,
) -> Option<(u32, u32)> {
    if let Some(choice) = cheapest_meeting(class, n, size, p, target, max_n, max_size, costs) {
        return Some(choice);
    }
    let share = target / std::f64::consts::SQRT_2;
    let ladder = sides(max_n);
    let top = *ladder.last().expect("at least one side");
    let (can_n, can_size) = (n < top, size < max_size);
    let mut grow_size = p.predicted_map > share && can_size;
    if !can_size && p.predicted_map >= target {
        return None;
    }
    let floor =
        p.predicted_map * 0.5f64.powi((max_size / size.max(1)).max(1).trailing_zeros() as i32);
    let sampling_share = if grow_size {
        share
    } else {
        (target * target - p.predicted_map * p.predicted_map).sqrt()
    };
    let sampling_share = if floor > target {
        sampling_share.max(0.5 * floor)
    } else {
        sampling_share
    };
    let grow_n = p.predicted_sampling > sampling_share && can_n;
    if p.predicted_sampling > sampling_share && !can_n {
        grow_size = can_size;
    }
    if !grow_n && !grow_size {
        return None;
    }
    let n2 = if grow_n {
        // The first side past n whose sampling error its order (and its factor) puts under the share.
        ladder
            .iter()
            .copied()
            .find(|&n2| n2 > n && sampling_at(class, n, p.predicted_sampling, n2) <= sampling_share)
            .unwrap_or(top)
    } else {
        n
    };
    Some((n2, if grow_size { size * 2 } else { size }))
}

impl AutoState {
    /// The grid (n, size) with the estimate, built unless it is the one held.
    fn hold(&mut self, fg: &FrameGpu, (n, size): (u32, u32)) -> Result<()> {
        self.frames.entry(size).or_insert_with(|| {
            let frame = crate::gpu::structs::GpuFrame {
                map_size: size,
                ..fg.frame
            };
            crate::gpu::readback::uniform_buffer(fg.ctx, "auto frame", &frame)
        });
        if self.grid.as_ref().is_none_or(|(key, _)| *key != (n, size)) {
            // The previous grid's maps go before the next one's are allocated.
            self.grid = None;
            let frame = self.frames[&size].clone();
            // One grid's maps at a time, kept from frame to frame while the choice holds (docs/reuse.md).
            let mut grid = fixed_samples::prepare_kept(
                fg,
                &regular_points(n, Layout::Centred),
                size,
                Some(frame),
                Some("auto"),
            )?;
            grid.estimate = Some(fixed_samples::Estimate::new(
                fg,
                n,
                Layout::Centred,
                grid.map_count(),
            )?);
            self.grid = Some(((n, size), grid));
        }
        Ok(())
    }

    /// A frame after the one that settled the choice: the grid alone (its V is the settling
    /// frame's, bit for bit), and that frame's record (its tries and prediction) and bound.
    fn run_settled(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        mut record: serde_json::Value,
        bound: Vec<f32>,
    ) -> Result<MethodOutput> {
        if let Some(i) = self.filter {
            // The frame cleared V; the filter writes it, as its fixed method does.
            let out = self.filters.run(i, fg, timer)?;
            self.reuse.add(&ReuseCounts::all_rendered(
                out.shadow_maps,
                fg.scene.render.shadow_map_size,
            ));
            record["maps_rendered"] = out.shadow_maps.into();
            record["estimated"] = false.into();
            return Ok(MethodOutput {
                shadow_maps: out.shadow_maps,
                syncs: 0,
                record,
                pictures: Vec::new(),
                bound: Some(bound),
            });
        }
        let (_, grid) = self.grid.as_mut().expect("reset holds the settled grid");
        let estimate = grid.estimate.take();
        // The frame cleared V, as for a fixed grid: no clear of its own (a submission more), so the
        // settled frame is that grid's frame, pass for pass.
        let out = grid.run(fg, timer, false);
        grid.estimate = estimate;
        let out = out?;
        self.reuse.add(&grid.reuse_counts().unwrap_or_default());
        // `tries` stays the settling frame's: how the choice was made.
        record["maps_rendered"] = out.shadow_maps.into();
        record["estimated"] = false.into();
        Ok(MethodOutput {
            shadow_maps: out.shadow_maps,
            syncs: 0,
            record,
            pictures: Vec::new(),
            bound: Some(bound),
        })
    }

    /// One grid rendered into V (cleared first) with the estimate; its prediction and bound.
    fn try_grid(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        geometry: &[bool],
        (n, size): (u32, u32),
    ) -> Result<(Try, Vec<f32>)> {
        self.hold(fg, (n, size))?;
        let grid = &mut self.grid.as_mut().expect("built above").1;
        let start = std::time::Instant::now();
        let out = render_into_cleared_v(grid, fg, timer)?;
        self.reuse.add(&grid.reuse_counts().unwrap_or_default());
        let e = grid.estimate.as_ref().expect("built with the estimate");
        timer.flush(fg.ctx);
        let sums = timer.cpu(crate::gpu::Stage::READBACK, || e.read(fg))?;
        let ms = start.elapsed().as_secs_f64() * 1e3;
        let (raw, bound) = e.predict(&sums, geometry)?;
        let prediction = calibration::calibrated(&raw, self.class, n);
        Ok((
            Try {
                n,
                map_size: size,
                maps: out.shadow_maps,
                ms,
                prediction,
                predicted_raw: raw.predicted_rmse,
            },
            bound,
        ))
    }
}

/// Whether a try's prediction settles the frame: at most the target, or, for the choice handed
/// on from the previous frame of a sequence (`handed_on`), within the band `hold` keeps a choice in.
fn acceptable(predicted: f64, target: f64, handed_on: bool) -> bool {
    if handed_on {
        super::hold::standing(predicted, target) != super::hold::Standing::Above
    } else {
        predicted <= target
    }
}

/// One grid's frame into V cleared first: a try replaces the one before it, and shade adds.
fn render_into_cleared_v(
    grid: &mut Prepared,
    fg: &FrameGpu,
    timer: &mut StageTimer,
) -> Result<MethodOutput> {
    fg.clear_visibility();
    grid.reset(fg)?;
    grid.run(fg, timer, false)
}

impl MethodState for AutoState {
    /// The grid the frame starts with is built before the clock, as a fixed method's is; only the
    /// grids a search moves on to are built inside the frame.
    fn reset(&mut self, fg: &FrameGpu) -> Result<()> {
        self.reuse = ReuseCounts::default();
        if self.settled.is_some() && self.filter.is_some() {
            // A settled filter renders alone; a search builds what it tries.
            return Ok(());
        }
        self.hold(fg, self.choice)
    }
    fn run(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        _pictures: bool,
    ) -> Result<MethodOutput> {
        if let Some((record, bound)) = &self.settled {
            return self.run_settled(fg, timer, record.clone(), bound.clone());
        }
        let target = self.method.target as f64;
        // The G-buffer pass is recorded, not yet submitted: flush before reading it.
        timer.flush(fg.ctx);
        let geometry = timer.cpu(crate::gpu::Stage::READBACK, || {
            fixed_samples::geometry_mask(fg)
        })?;
        let mut tries: Vec<Try> = Vec::new();
        let mut bound;
        // The state's first search also steps down: from a try that meets the target, to a cheaper
        // grid predicted to meet it; where that one misses, back to the cheapest that met.
        let mut down = !self.recalled && !self.searched;
        self.searched = true;
        let mut met: Option<(u32, u32)> = None;
        // Settled: the target met, or nothing left to grow. A search cut at MAX_TRIES goes on
        // next frame.
        let settles = loop {
            let (t, b) = self.try_grid(fg, timer, &geometry, self.choice)?;
            bound = b;
            tries.push(t);
            let handed_on = self.recalled && tries.len() == 1;
            // A handed-on choice whose prediction fell below the band may step down to a cheaper
            // grid (the band's lower edge, `hold::standing`); within it, it holds.
            if handed_on
                && super::hold::standing(t.prediction.predicted_rmse, target)
                    == super::hold::Standing::Below
            {
                down = true;
            }
            if acceptable(t.prediction.predicted_rmse, target, handed_on) {
                // A step down is only taken with a try to spare for the way back.
                let tried: Vec<(u32, u32)> = tries.iter().map(|t| (t.n, t.map_size)).collect();
                let step = if down && tries.len() + 1 < MAX_TRIES {
                    cheaper_meeting(
                        self.class,
                        t.n,
                        t.map_size,
                        &t.prediction,
                        target,
                        self.method.max_n,
                        self.method.max_size,
                        &self.costs,
                        &tried,
                    )
                } else {
                    None
                };
                met = Some((t.n, t.map_size));
                match step {
                    Some(next) => {
                        self.choice = next;
                        continue;
                    }
                    None => break true,
                }
            }
            if let Some(back) = met.filter(|_| down) {
                down = false;
                self.choice = back;
                continue;
            }
            if tries.len() == MAX_TRIES {
                break false;
            }
            match next_choice(
                self.class,
                t.n,
                t.map_size,
                &t.prediction,
                target,
                self.method.max_n,
                self.method.max_size,
                &self.costs,
            ) {
                Some(next) => self.choice = next,
                None => break true,
            }
        };
        if self.certifying.is_some() {
            // The estimate's search found the first guess; the bound decides (docs/certify.md §5).
            return self.certified_frame(fg, timer, &geometry, tries, bound, settles);
        }
        let last = *tries.last().expect("one try at least");
        // The previous frame's choice, kept within KEEP of the target.
        let kept = self.recalled
            && tries.len() == 1
            && last.prediction.predicted_rmse > target
            && acceptable(last.prediction.predicted_rmse, target, true);
        let met = last.prediction.predicted_rmse <= target || kept;
        let mut maps: u32 = tries.iter().map(|t| t.maps).sum();
        // The one-map candidates: where a grid met the target, judged against a finer grid; where
        // none can, against the grid the frame renders. A sequence's later frames check them only
        // where the previous frame chose one: a grid does not turn into a filter there.
        self.filter = None;
        let mut filter_record = serde_json::Value::Null;
        let mut predicted = last.prediction.predicted_rmse;
        let mut difference = 0.0;
        let filter_factor = calibration::factors(self.class).largest();
        let check = (met || settles)
            && !self.filters.is_empty()
            && (!self.recalled || self.handed_filter.is_some());
        if check {
            let mut filters =
                std::mem::replace(&mut self.filters, Candidates::new(Vec::new(), Vec::new()));
            let handed = self.handed_filter.clone();
            // A reference grid's maps are counted by its try; the candidates' are rendered.
            let counted = |r: &ReuseCounts| r.rendered + r.kept + r.redrawn;
            let grids_before = counted(&self.reuse);
            let outcome = if met {
                // F = sqrt(D² − σ²) takes the grid's own error out of the difference: σ is the
                // estimate's raw reading there (a calibrated σ, larger, would hide the filter's
                // error), and F is then calibrated by the larger of the two factors.
                let grid = Met {
                    rmse: last.predicted_raw,
                    ms: last.ms,
                };
                let (max_n, max_size) = (self.method.max_n, self.method.max_size);
                let mut reference = |timer: &mut StageTimer| -> Result<Option<Reference>> {
                    let Some(grid) = cheapest_meeting(
                        self.class,
                        last.n,
                        last.map_size,
                        &last.prediction,
                        target * REFERENCE,
                        max_n,
                        max_size,
                        &self.costs,
                    ) else {
                        return Ok(None);
                    };
                    let (r, bound) = self.try_grid(fg, timer, &geometry, grid)?;
                    let record = serde_json::to_value(r)
                        .map_err(|e| crate::Error::Limit(format!("auto: reference record: {e}")))?;
                    Ok(Some(Reference {
                        rmse: r.predicted_raw,
                        bound,
                        maps: r.maps,
                        record,
                    }))
                };
                let accept = |p: f64, handed: bool| acceptable(filter_factor * p, target, handed);
                filters.check(
                    fg,
                    timer,
                    &geometry,
                    grid,
                    target * SCREEN / filter_factor,
                    &mut reference,
                    &accept,
                    handed.as_deref(),
                )
            } else {
                // Out of reach: a candidate no worse than the grid, as far as the estimate can tell.
                let grid = Met {
                    rmse: last.prediction.predicted_rmse,
                    ms: last.ms,
                };
                filters.check_out_of_reach(
                    fg,
                    timer,
                    &geometry,
                    grid,
                    &bound,
                    KEEP,
                    handed.as_deref(),
                )
            };
            self.filters = filters;
            let outcome = outcome?;
            maps += outcome.maps;
            let reference_maps = counted(&self.reuse) - grids_before;
            self.reuse.add(&ReuseCounts::all_rendered(
                outcome.maps.saturating_sub(reference_maps),
                fg.scene.render.shadow_map_size,
            ));
            if let Some((i, p, b)) = outcome.chosen {
                self.filter = Some(i);
                // Met: the filter's F. Out of reach, p is its difference from the grid, and the
                // filter is read as no worse than the grid's prediction, which stays.
                if met {
                    predicted = filter_factor * p;
                } else {
                    difference = p;
                }
                bound = b;
            }
            filter_record = serde_json::json!({ "reference": outcome.reference, "chosen": self.filter.map(|i| self.filters.label(i)), "checks": outcome.checks, "left_out": self.filters.left_out() });
        }
        if !met && !self.warned {
            self.warned = true;
            let renders = self.filter.map_or(String::new(), |i| format!("; {} differs from that grid by {difference:.5} (RMS), within its predicted error, and is rendered instead", self.filters.label(i)));
            crate::progress::suspend(|| {
                eprintln!(
                    "auto: target RMSE {} is out of reach within n ≤ {} and {}² maps: the best predicted is {:.5} (regular:n={},layout=centred at {}² maps){renders}",
                    self.method.target, self.method.max_n, self.method.max_size, last.prediction.predicted_rmse, last.n, last.map_size
                )
            });
        }
        let mut record = serde_json::json!({
            "chosen": { "n": last.n, "layout": "centred", "map_size": last.map_size, "spec": format!("regular:n={},layout=centred", last.n) },
            "target": self.method.target,
            // Met only where the prediction the frame reports is at most the target: a choice kept
            // within KEEP of it (a sequence's) is `kept`, not met.
            "target_met": predicted <= target,
            "tries": tries,
            "predicted_rmse": predicted,
            "predicted_sampling": last.prediction.predicted_sampling,
            "predicted_map": last.prediction.predicted_map,
            "map_cost": { "model": self.method.cost.name(), "per_map": self.costs.0.iter().map(|(z, c)| (z.to_string(), serde_json::json!(c))).collect::<serde_json::Map<_, _>>(), "pricing_ms": self.pricing_ms },
        });
        record["filter"] = filter_record;
        if let Some(i) = self.filter {
            // What the frame renders: the grid stays in `chosen` as the reference it was judged by.
            record["renders"] = self.filters.label(i).into();
        }
        record["maps_rendered"] = maps.into();
        record["estimated"] = true.into();
        record["kept"] = kept.into();
        if settles {
            self.settled = Some((record.clone(), bound.clone()));
        }
        Ok(MethodOutput {
            shadow_maps: maps,
            syncs: 1 + tries.len() as u32,
            record,
            pictures: Vec::new(),
            bound: Some(bound),
        })
    }
    fn camera_moved(&mut self) {
        self.settled = None;
    }
    /// Every grid the frame rendered, and the one-map candidates' maps (rendered).
    fn reuse(&self) -> Option<ReuseCounts> {
        Some(self.reuse)
    }
    fn release_maps(&mut self) -> Vec<crate::render::kept_maps::KeptMaps> {
        self.grid
            .as_mut()
            .and_then(|(_, g)| g.release())
            .into_iter()
            .collect()
    }
    /// The choice, so the next frame of a sequence starts from it (and only rises from there).
    fn memory(&self) -> Option<serde_json::Value> {
        Some(serde_json::json!([
            self.choice.0,
            self.choice.1,
            self.filter.map(|i| self.filters.name(i))
        ]))
    }
    fn recall(&mut self, memory: &serde_json::Value) {
        if let (Some(n), Some(size)) = (memory[0].as_u64(), memory[1].as_u64()) {
            self.choice = (n as u32, size as u32);
            self.recalled = true;
            self.handed_filter = memory[2].as_str().map(String::from);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tx() -> Costs {
        Costs::texels(2048)
    }

    fn p(sampling: f64, map: f64) -> Prediction {
        pa(sampling, map, 0.0)
    }

    /// With `averaging` of the maps' error falling with n.
    fn pa(sampling: f64, map: f64, averaging: f64) -> Prediction {
        Prediction {
            predicted_rmse: (sampling * sampling + map * map).sqrt(),
            predicted_sampling: sampling,
            predicted_map: map,
            predicted_quantization: map,
            predicted_bias: 0.0,
            predicted_map_averaging: averaging,
        }
    }

    #[test]
    fn the_cheapest_grid_predicted_to_meet_the_target() {
        // Maps well under the target: sampling gets sqrt(0.01² − map²) ≈ 0.00998 and is 1.42× over
        // it, so n grows by 1.42^(1/1.5) ≈ 1.26: 5 → 6.3 → 7, at the same maps.
        let share = 0.01 / std::f64::consts::SQRT_2;
        assert_eq!(
            next_choice(
                Class::Plane,
                5,
                512,
                &p(2.0 * share, 0.1 * share),
                0.01,
                17,
                2048,
                &tx()
            ),
            Some((7, 512))
        );
        // The maps alone over the target: doubling them (predicted 0.0053 + 0.0035) meets it.
        assert_eq!(
            next_choice(
                Class::Plane,
                5,
                512,
                &p(0.5 * share, 1.5 * share),
                0.01,
                17,
                2048,
                &tx()
            ),
            Some((5, 1024))
        );
        // Both at 0.0078 at 256²: 4×4 there would be predicted to meet 0.01 (16 maps of cost ½),
        // but 256² maps are not a grid the calibration was fitted on: 3×3 at 512² (0.0087, cost 9),
        // before 4×4 there (0.0095 with the even side's factor, cost 16).
        assert_eq!(
            next_choice(
                Class::Plane,
                3,
                256,
                &p(1.1 * share, 1.1 * share),
                0.01,
                17,
                2048,
                &tx()
            ),
            Some((3, 512))
        );
        // Maps at their largest, their error under the target: n takes the rest of it.
        // sampling share = sqrt(0.01² − 0.009²) = 0.00436; 0.006 / 0.00436 = 1.38 → 5 · 1.24 = 6.2,
        // and the next odd side is 7.
        assert_eq!(
            next_choice(
                Class::Plane,
                5,
                2048,
                &p(0.006, 0.009),
                0.01,
                17,
                2048,
                &tx()
            ),
            Some((7, 2048))
        );
        // Maps at their largest and their error alone over the target: out of reach.
        assert_eq!(
            next_choice(
                Class::Plane,
                5,
                2048,
                &p(0.001, 0.011),
                0.01,
                17,
                2048,
                &tx()
            ),
            None
        );
        // n at its largest: nothing is predicted to meet it, and the maps take the excess.
        assert_eq!(
            next_choice(
                Class::Plane,
                17,
                512,
                &p(1.5 * share, 0.5 * share),
                0.01,
                17,
                2048,
                &tx()
            ),
            Some((17, 1024))
        );
        // Nothing left to grow.
        assert_eq!(
            next_choice(
                Class::Plane,
                17,
                2048,
                &p(1.5 * share, 0.5 * share),
                0.01,
                17,
                2048,
                &tx()
            ),
            None
        );
        // Maps whose error would miss the target even at 2048² (grove at 128²: 0.196 at 512²,
        // floor 0.049 against 0.012): nothing meets it, so n grows only to keep sampling under
        // half the floor, 3 · (0.031 / 0.0245)^(2/3) = 3.5 → 5, not to 0.012 / √2 (which asks for 9).
        // 4×4 would be 0.035 with the even side's factor (2.28 against 1.32).
        assert_eq!(
            next_choice(
                Class::Plane,
                3,
                512,
                &p(0.031, 0.196),
                0.012,
                17,
                2048,
                &tx()
            ),
            Some((5, 1024))
        );
        assert_eq!(
            next_choice(
                Class::Plane,
                5,
                1024,
                &p(0.020, 0.150),
                0.012,
                17,
                2048,
                &tx()
            ),
            Some((5, 2048))
        );
        assert_eq!(
            next_choice(
                Class::Plane,
                5,
                2048,
                &p(0.016, 0.117),
                0.012,
                17,
                2048,
                &tx()
            ),
            None
        );
        // The ladder: odd sides, and even ones to 6 (their own factor), maps from 512² (256² alone
        // under max_size = 256).
        assert_eq!(
            (sides(17), sides(8), sides(2)),
            (
                vec![2, 3, 4, 5, 6, 7, 9, 11, 13, 15, 17],
                vec![2, 3, 4, 5, 6, 7],
                vec![2]
            )
        );
        assert_eq!(
            (sizes(2048), sizes(512), sizes(256)),
            (vec![512, 1024, 2048], vec![512], vec![256])
        );
        assert_eq!(
            next_choice(
                Class::Plane,
                2,
                256,
                &p(0.02, 0.02),
                0.01,
                2,
                256,
                &Costs::texels(256)
            ),
            None
        );
        // The same maps under a target that 2048² meets (0.049 and 0.031 against 0.06) and 1024²
        // cannot (0.098): straight to 2048².
        assert_eq!(
            next_choice(
                Class::Plane,
                3,
                512,
                &p(0.031, 0.196),
                0.06,
                17,
                2048,
                &tx()
            ),
            Some((3, 2048))
        );
    }

    #[test]
    fn maps_error_that_averages_over_samples_buys_samples_not_texels() {
        // overlapping-occluders-like at 3×3, 512²: sampling 0.02, maps 0.023 of which 0.021
        // averages over samples. Against 0.012: with the averaging part, 7×7 at 1024² (predicted
        // maps 0.0065, sampling 0.0056; cost 98); without it the maps must shrink by texels alone
        // (7×7 at 1024² would read 0.0128), and 5×5 at 2048² (cost 100) is the cheapest.
        let with = pa(0.02, 0.023, 0.021);
        assert_eq!(
            next_choice(Class::Plane, 3, 512, &with, 0.012, 17, 2048, &tx()),
            Some((7, 1024))
        );
        assert!(
            (predicted_at(Class::Plane, 3, 512, &with, 7, 1024) - 0.00859).abs() < 1e-4,
            "{}",
            predicted_at(Class::Plane, 3, 512, &with, 7, 1024)
        );
        assert_eq!(
            next_choice(
                Class::Plane,
                3,
                512,
                &p(0.02, 0.023),
                0.012,
                17,
                2048,
                &tx()
            ),
            Some((5, 2048))
        );
        // Every bit of it averaging: at the same maps, m falls as 1/n: 3 → 9 thirds it.
        let all = pa(0.0, 0.03, 0.03);
        assert!((predicted_at(Class::Plane, 3, 512, &all, 9, 512) - 0.01).abs() < 1e-12);
        assert_eq!(
            next_choice(Class::Plane, 3, 512, &all, 0.0101, 17, 512, &tx()),
            Some((9, 512))
        );
        // With larger maps allowed, 3×3 at 2048² (0.0075, cost 36) is cheaper than 9×9 at 512² (81).
        assert_eq!(
            next_choice(Class::Plane, 3, 512, &all, 0.0101, 17, 2048, &tx()),
            Some((3, 2048))
        );
    }

    #[test]
    fn measured_prices_move_the_choice_to_larger_maps_where_they_cost_little_more() {
        // bunny at 128² from 3×3 at 512² (predicted 0.0315: sampling 0.0161, maps 0.0270 of which
        // 0.0218 averages), priced as lavapipe's compute raster timed it: 31.0, 36.2 and 51.6 ms per
        // map at 512², 1024² and 2048². Under `texels` a 2048² map costs four 512² ones; measured, 1.7.
        // Against 0.012: 7×7 at 1024² (98 units) under `texels`, 5×5 at 2048² (1290 ms) measured.
        let bunny = pa(0.0161, 0.0270, 0.0218);
        let timed = Costs(vec![(512, 31.0), (1024, 36.2), (2048, 51.6)]);
        assert_eq!(
            next_choice(Class::Plane, 3, 512, &bunny, 0.012, 17, 2048, &tx()),
            Some((7, 1024))
        );
        assert_eq!(
            next_choice(Class::Plane, 3, 512, &bunny, 0.012, 17, 2048, &timed),
            Some((5, 2048))
        );
        // At 0.03 the maps' part decides, and an even side is on the ladder: 4×4 at 512² (0.0291
        // with the even side's sampling factor, 16 units) under `texels`, before 3×3 at 1024² (18);
        // measured, 3×3 at 1024² (326 ms against 496).
        assert_eq!(
            next_choice(Class::Plane, 3, 512, &bunny, 0.03, 17, 2048, &tx()),
            Some((4, 512))
        );
        assert!(
            (predicted_at(Class::Plane, 3, 512, &bunny, 4, 512) - 0.0291).abs() < 1e-4,
            "{}",
            predicted_at(Class::Plane, 3, 512, &bunny, 4, 512)
        );
        assert_eq!(
            next_choice(Class::Plane, 3, 512, &bunny, 0.03, 17, 2048, &timed),
            Some((3, 1024))
        );
        assert_eq!(
            next_choice(Class::Plane, 3, 512, &bunny, 0.02, 17, 2048, &timed),
            next_choice(Class::Plane, 3, 512, &bunny, 0.02, 17, 2048, &tx())
        );
        // A size above max_size is never priced, so never chosen: 7×7 at 512² (49) before 5×5 at 1024² (50).
        assert_eq!(
            Costs::texels(1024)
                .0
                .iter()
                .map(|c| c.0)
                .collect::<Vec<_>>(),
            vec![512, 1024]
        );
        assert_eq!(
            next_choice(
                Class::Plane,
                3,
                512,
                &bunny,
                0.02,
                17,
                1024,
                &Costs::texels(1024)
            ),
            Some((7, 512))
        );
    }

    #[test]
    fn cows_takes_2048_maps_where_no_1024_grid_is_predicted_to_meet_the_target_for_less() {
        // cows at 128² from 3×3 at 512² (predicted 0.0556: sampling 0.0165, maps 0.0531 of which
        // 0.0289 averages), at the prices a settled frame gave on lavapipe: 16.4, 21.2 and 39.1 ms
        // per map (results/budget-prices/). Against 0.03, 3×3 at 1024² (the oracle, measured
        // 0.0268) is predicted at 0.031: 3×3 at 2048² (352) beats 5×5 at 1024² (530), and would
        // lose only to a 2048² map priced above 25/9 = 2.78 times a 1024² one.
        let cows = pa(0.0165, 0.0531, 0.0289);
        assert!(
            (predicted_at(Class::Plane, 3, 512, &cows, 3, 1024) - 0.0313).abs() < 1e-4,
            "{}",
            predicted_at(Class::Plane, 3, 512, &cows, 3, 1024)
        );
        let frame = Costs(vec![(512, 16.4), (1024, 21.2), (2048, 39.1)]);
        assert_eq!(
            next_choice(Class::Plane, 3, 512, &cows, 0.03, 17, 2048, &frame),
            Some((3, 2048))
        );
        let dear = |ratio: f64| Costs(vec![(512, 16.4), (1024, 21.2), (2048, 21.2 * ratio)]);
        assert_eq!(
            next_choice(Class::Plane, 3, 512, &cows, 0.03, 17, 2048, &dear(2.7)),
            Some((3, 2048))
        );
        assert_eq!(
            next_choice(Class::Plane, 3, 512, &cows, 0.03, 17, 2048, &dear(2.8)),
            Some((5, 1024))
        );
        // Against 0.02 no grid at 1024² is predicted to meet it (the maps' part alone, halved,
        // stays over): 2048² maps at any price.
        assert_eq!(
            next_choice(Class::Plane, 3, 512, &cows, 0.02, 17, 2048, &dear(10.0)),
            Some((5, 2048))
        );
    }

    #[test]
    fn a_first_search_steps_down_to_a_cheaper_grid_predicted_to_meet_the_target() {
        // 5×5 at 512² reads 0.0187 against 0.02 (sampling 0.005, maps 0.018 of which 0.012
        // averages). 3×3 at 1024² is predicted at 0.0162 (sampling 0.005 · (5/3)^1.5, maps
        // sqrt(0.018² + 0.012² · 16/9) / 2) for 18 units against 25; 3×3 at 512² at 0.0241.
        let five = pa(0.005, 0.018, 0.012);
        assert!(
            (predicted_at(Class::Plane, 5, 512, &five, 3, 1024) - 0.01615).abs() < 1e-4,
            "{}",
            predicted_at(Class::Plane, 5, 512, &five, 3, 1024)
        );
        assert_eq!(
            cheaper_meeting(
                Class::Plane,
                5,
                512,
                &five,
                0.02,
                17,
                2048,
                &tx(),
                &[(5, 512)]
            ),
            Some((3, 1024))
        );
        // Tried already (it missed): nothing else cheaper is predicted to meet it.
        assert_eq!(
            cheaper_meeting(
                Class::Plane,
                5,
                512,
                &five,
                0.02,
                17,
                2048,
                &tx(),
                &[(5, 512), (3, 1024)]
            ),
            None
        );
        // A smaller map raises the maps' error as a larger one lowers it: 4× its square per halving.
        assert!((predicted_at(Class::Plane, 3, 512, &p(0.0, 0.01), 3, 256) - 0.02).abs() < 1e-12);
        // At 0.015 no grid of fewer than 25 units is predicted to meet it: 4×4 at 512² (16 units)
        // reads 0.0235 with the even side's factor, and 256² maps are off the ladder.
        assert_eq!(
            cheaper_meeting(
                Class::Plane,
                5,
                512,
                &five,
                0.015,
                17,
                2048,
                &tx(),
                &[(5, 512)]
            ),
            None
        );
    }

    #[test]
    fn a_handed_on_choice_is_kept_within_a_margin() {
        assert!(acceptable(0.015, 0.015, false) && !acceptable(0.0151, 0.015, false));
        assert!(
            acceptable(0.017, 0.015, true),
            "within 15%: the previous frame's grid stays"
        );
        assert!(!acceptable(0.0175, 0.015, true), "past 15%: it grows");
    }

    #[test]
    fn parameters_are_checked() {
        for (spec, expect) in [
            ("auto:target=0", "target"),
            ("auto:max_n=1", "max_n"),
            ("auto:max_size=300", "max_size"),
            ("auto:target=x", "target"),
            ("auto:cost=guess", "cost"),
            ("auto:delta=1", "delta = 1 is outside (0, 1)"),
            ("auto:delta=0", "delta"),
            ("auto:pixels=-3", "pixels"),
        ] {
            let e = super::super::Method::parse(spec, &[])
                .err()
                .unwrap_or_else(|| panic!("{spec} parsed"))
                .to_string();
            assert!(e.contains("auto") && e.contains(expect), "{spec}: {e}");
        }
        assert_eq!(
            super::super::Method::parse("auto:target=0.01", &[])
                .unwrap()
                .label(),
            "auto:target=0.01"
        );
    }
}
