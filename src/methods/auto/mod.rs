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
    ChoiceDecl, Family, MethodInfo, MethodOutput, MethodState, Param, ParamDecl, ParamMap,
    ShadowMethod,
};
use crate::gpu::timing::StageTimer;
use crate::methods::calibration::{self, Class};
use crate::methods::estimate::Prediction;
use crate::methods::fixed_samples::{self, regular_points, Layout, Prepared};
use crate::render::kept_maps::ReuseCounts;
use crate::stages::FrameGpu;
use crate::Result;
pub use filter::Check;
use filter::{Against, Candidates, Met, OutOfReach, Reference, Scope};
pub use record::{AutoRecord, Chosen, FilterCheck, MapCost};
pub use search::{predicted_at, At, Costs, Ladder, SAMPLING_ORDER};
pub(crate) use search::{sides, sizes};
use std::collections::BTreeMap;

mod certified;
pub(crate) mod filter;
pub(crate) mod price;
pub(crate) mod record;
pub(crate) mod search;

pub(crate) const TARGET: ParamDecl<f32> = ParamDecl::new(
    "target",
    "0.015",
    0.0005,
    0.5,
    "RMSE of V to reach, 0.0005..=0.5 (predicted without a reference; docs/error-estimate.md)",
);
pub(crate) const MAX_N: ParamDecl<u32> = ParamDecl::new(
    "max_n",
    "17",
    2,
    32,
    "largest grid side it may choose, 2..=32",
);
/// `parse` checks it is one of `SIZES`.
pub(crate) const MAX_SIZE: ParamDecl<u32> = ParamDecl::new(
    "max_size",
    "2048",
    0,
    u32::MAX,
    "largest map size it may choose: 256, 512, 1024 or 2048",
);
pub(crate) const COST: ChoiceDecl = ChoiceDecl::new(
    "cost",
    "measured",
    &["measured", "texels"],
    "how it prices a map of each size: `measured` (what a map of each size adds to this scene's frame on this device, timed before the clock, once per process) or `texels` (double per doubling of the side: the same choice on every device)",
);
/// K: the exact pixels a decision draws (`certified`).
pub(crate) const PIXELS: ParamDecl<u32> = ParamDecl::new(
    "pixels",
    "2048",
    0,
    1 << 20,
    "K: pixels whose exact truth certifies the choice (docs/certify.md): the cheapest candidate whose bound on its RMSE is at most the target is rendered; 0 decides by the estimate alone",
);
/// `parse` checks the open range (0, 1).
pub(crate) const DELTA: ParamDecl<f32> = ParamDecl::new(
    "delta",
    "0.05",
    f32::MIN,
    f32::MAX,
    "each candidate's bound holds with probability 1 − delta, in (0, 1)",
);

pub(crate) const INFO: MethodInfo = MethodInfo {
    name: "auto",
    family: Family::MultiSample,
    summary: "error budget: the centred grid's n and map size grown until the predicted RMSE of V meets the target (or one filtered map, where it is predicted to), then kept while the camera stays",
    params: &[
        TARGET.param(),
        MAX_N.param(),
        MAX_SIZE.param(),
        COST.param(),
        Param { key: "filters", default: "pcss+msm", help: "one-map methods checked against the grid that meets the target (or, out of reach, the best grid tried), joined by + (e.g. pcss, or pcss+msm+vsm), or none: one predicted to meet it (out of reach: to err no more than that grid) that took less time is rendered instead; the default leaves out those that refuse the scene's light" },
        PIXELS.param(),
        DELTA.param(),
    ],
    parse: |p: &ParamMap| {
        let target = TARGET.get(p, "auto")?;
        let max_n = MAX_N.get(p, "auto")?;
        let max_size = MAX_SIZE.get(p, "auto")?;
        if !SIZES.contains(&max_size) {
            return Err(crate::Error::Param(format!("auto: max_size = {max_size}: use one of 256, 512, 1024, 2048")));
        }
        let cost = match COST.get(p)? {
            "texels" => CostModel::Texels,
            _ => CostModel::Measured,
        };
        let filters = p.get("filters").map_or(DEFAULT_FILTERS, String::as_str).to_string();
        filter::parse_list(&filters)?;
        let pixels = PIXELS.get(p, "auto")?;
        let delta = DELTA.get(p, "auto")?;
        if !(delta > 0.0 && delta < 1.0) {
            return Err(crate::Error::Param(format!("auto: delta = {delta} is outside (0, 1): each bound holds with probability 1 − delta")));
        }
        Ok(std::sync::Arc::new(Auto { target, max_n, max_size, cost, filters, pixels, delta }))
    },
};

/// The one-map candidates unless `filters` says otherwise: `pcss` for the soft edges of small
/// scenes, `msm` for the acne-prone ones (`grazing-ground`: 0.126 against the grid's 0.189).
pub(crate) const DEFAULT_FILTERS: &str = "pcss+msm";

/// The map sizes it steps through.
pub(crate) const SIZES: [u32; 4] = [256, 512, 1024, 2048];
/// The first frame's choice: the smallest grid with half sets in both axes at 512² maps.
const START: (u32, u32) = (3, 512);
/// At most this many tries in one frame (each a full render of a grid).
const MAX_TRIES: usize = 8;
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
pub(crate) struct Auto {
    pub(crate) target: f32,
    pub(crate) max_n: u32,
    pub(crate) max_size: u32,
    pub(crate) cost: CostModel,
    /// `none`, or one-map methods joined by `+` (filter::parse_list).
    pub(crate) filters: String,
    /// K, the exact pixels that certify the choice; 0: the estimate alone decides.
    pub(crate) pixels: u32,
    pub(crate) delta: f32,
}

/// How a map of each size is priced in the search (docs/error-estimate.md §6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum CostModel {
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
            ladder: Ladder::new(
                Class::of(fg.scene.emitter.kind()),
                self.max_n,
                self.max_size,
                costs,
            ),
            pricing_ms,
            searched: false,
            filters,
            filter: None,
            handed_filter: None,
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
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
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

impl Try {
    /// The try as the search reads it.
    pub(crate) fn at(&self) -> At {
        At::new(self.n, self.map_size, self.prediction)
    }
}

pub(crate) struct AutoState {
    method: Auto,
    /// The grid the next frame starts with.
    choice: (u32, u32),
    /// The grid last tried: one at a time, as each may hold the whole map budget.
    grid: Option<((u32, u32), Prepared)>,
    /// The frame uniform of each map size.
    frames: BTreeMap<u32, wgpu::Buffer>,
    /// The out-of-reach line went to `progress::notice` (once per state).
    warned: bool,
    /// The frame that settled `choice`: its record and bound. Later frames of this state (same
    /// scene, light and camera) would predict the same, so they render the grid alone.
    settled: Option<(AutoRecord, Vec<f32>)>,
    /// The choice came from the previous frame of a sequence (`recall`): its first try is kept
    /// within KEEP of the target.
    recalled: bool,
    /// The grids it chooses among and the price of a map of each size.
    ladder: Ladder,
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
    /// `pixels` > 0: the exact truth that certifies the choice (`certified`).
    certifying: Option<certified::Certifying>,
    /// This frame's maps rendered and kept, over its tries.
    reuse: ReuseCounts,
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
        mut record: AutoRecord,
        bound: Vec<f32>,
    ) -> Result<MethodOutput> {
        if let Some(i) = self.filter {
            // The frame cleared V; the filter writes it, as its fixed method does.
            let out = self.filters.run(i, fg, timer)?;
            self.reuse.add(&ReuseCounts::all_rendered(
                out.shadow_maps,
                fg.scene.render.shadow_map_size,
            ));
            (record.maps_rendered, record.estimated) = (out.shadow_maps, false);
            return Ok(MethodOutput {
                shadow_maps: out.shadow_maps,
                syncs: 0,
                record: record.to_value()?,
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
        (record.maps_rendered, record.estimated) = (out.shadow_maps, false);
        Ok(MethodOutput {
            shadow_maps: out.shadow_maps,
            syncs: 0,
            record: record.to_value()?,
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
        let prediction = calibration::calibrated(&raw, self.ladder.class, n);
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
        // The G-buffer pass is recorded, not yet submitted: flush before reading it.
        timer.flush(fg.ctx);
        let geometry = timer.cpu(crate::gpu::Stage::READBACK, || {
            fixed_samples::geometry_mask(fg)
        })?;
        let search = self.search(fg, timer, &geometry)?;
        if self.certifying.is_some() {
            // The estimate's search found the first guess; the bound decides (docs/certify.md §5).
            return self.certified_frame(fg, timer, &geometry, search);
        }
        let mut frame = self.judged(search);
        self.check_filters(fg, timer, &geometry, &mut frame)?;
        frame.warning = self.out_of_reach(&frame);
        let record = self.record(&frame);
        if frame.search.settles {
            self.settled = Some((record.clone(), frame.search.bound.clone()));
        }
        let record = record.to_value()?;
        Ok(MethodOutput {
            shadow_maps: frame.maps,
            syncs: 1 + frame.search.tries.len() as u32,
            record,
            pictures: Vec::new(),
            bound: Some(frame.search.bound),
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

/// One frame's search over the grids: its tries, the bound of the last, whether it may still
/// step down, the cheapest grid that met the target so far, and whether it settled.
struct Search {
    tries: Vec<Try>,
    bound: Vec<f32>,
    /// The state's first search also steps down: from a try that meets the target, to a cheaper
    /// grid predicted to meet it; where that one misses, back to the cheapest that met.
    down: bool,
    met: Option<(u32, u32)>,
    /// Settled: the target met, or nothing left to grow. A search cut at MAX_TRIES goes on next
    /// frame.
    settles: bool,
}

/// The frame as the search and the one-map check leave it, for its record.
struct Judged {
    search: Search,
    /// The last try, what the frame renders unless a filter is chosen.
    last: Try,
    /// The previous frame's choice, kept within KEEP of the target.
    kept: bool,
    /// The last try's prediction met the target, or it was kept.
    met: bool,
    /// The maps rendered: every try's, then the filters' and the reference's.
    maps: u32,
    /// The frame's predicted RMSE: the last try's, or the chosen filter's F where a grid met it.
    predicted: f64,
    /// Out of reach: the chosen filter's difference from the grid.
    difference: f64,
    filter_record: Option<FilterCheck>,
    /// Out of reach: the line that says so.
    warning: Option<String>,
}

impl AutoState {
    /// The search: grids tried from the current choice until one settles the frame or MAX_TRIES
    /// is reached (`next_step`).
    fn search(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        geometry: &[bool],
    ) -> Result<Search> {
        let mut search = Search {
            tries: Vec::new(),
            bound: Vec::new(),
            down: !self.recalled && !self.searched,
            met: None,
            settles: false,
        };
        self.searched = true;
        loop {
            let (t, b) = self.try_grid(fg, timer, geometry, self.choice)?;
            search.bound = b;
            search.tries.push(t);
            if let Some(settles) = self.next_step(&mut search) {
                search.settles = settles;
                return Ok(search);
            }
        }
    }

    /// After a try: moves `choice` to the next grid to try and answers None, or ends the search
    /// with whether it settled.
    fn next_step(&mut self, s: &mut Search) -> Option<bool> {
        let target = self.method.target as f64;
        let t = *s.tries.last().expect("one try at least");
        let handed_on = self.recalled && s.tries.len() == 1;
        // A handed-on choice whose prediction fell below the band may step down to a cheaper
        // grid (the band's lower edge, `hold::standing`); within it, it holds.
        if handed_on
            && super::hold::standing(t.prediction.predicted_rmse, target)
                == super::hold::Standing::Below
        {
            s.down = true;
        }
        if acceptable(t.prediction.predicted_rmse, target, handed_on) {
            // A step down is only taken with a try to spare for the way back.
            let tried: Vec<(u32, u32)> = s.tries.iter().map(|t| (t.n, t.map_size)).collect();
            let step = if s.down && s.tries.len() + 1 < MAX_TRIES {
                self.ladder.cheaper_meeting(&t.at(), target, &tried)
            } else {
                None
            };
            s.met = Some((t.n, t.map_size));
            return match step {
                Some(next) => {
                    self.choice = next;
                    None
                }
                None => Some(true),
            };
        }
        if let Some(back) = s.met.filter(|_| s.down) {
            s.down = false;
            self.choice = back;
            return None;
        }
        if s.tries.len() == MAX_TRIES {
            return Some(false);
        }
        match self.ladder.next_choice(&t.at(), target) {
            Some(next) => {
                self.choice = next;
                None
            }
            None => Some(true),
        }
    }

    /// The search's outcome read against the target, before the one-map check.
    fn judged(&self, search: Search) -> Judged {
        let target = self.method.target as f64;
        let last = *search.tries.last().expect("one try at least");
        // The previous frame's choice, kept within KEEP of the target.
        let kept = self.recalled
            && search.tries.len() == 1
            && last.prediction.predicted_rmse > target
            && acceptable(last.prediction.predicted_rmse, target, true);
        let met = last.prediction.predicted_rmse <= target || kept;
        let maps = search.tries.iter().map(|t| t.maps).sum();
        Judged {
            search,
            last,
            kept,
            met,
            maps,
            predicted: last.prediction.predicted_rmse,
            difference: 0.0,
            filter_record: None,
            warning: None,
        }
    }

    /// The one-map candidates: where a grid met the target, judged against a finer grid; where
    /// none can, against the grid the frame renders. A sequence's later frames check them only
    /// where the previous frame chose one: a grid does not turn into a filter there.
    fn check_filters(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        geometry: &[bool],
        frame: &mut Judged,
    ) -> Result<()> {
        self.filter = None;
        let check = (frame.met || frame.search.settles)
            && !self.filters.is_empty()
            && (!self.recalled || self.handed_filter.is_some());
        if !check {
            return Ok(());
        }
        let target = self.method.target as f64;
        let filter_factor = calibration::factors(self.ladder.class).largest();
        let last = frame.last;
        let mut filters =
            std::mem::replace(&mut self.filters, Candidates::new(Vec::new(), Vec::new()));
        let handed = self.handed_filter.clone();
        // A reference grid's maps are counted by its try; the candidates' are rendered.
        let counted = |r: &ReuseCounts| r.rendered + r.kept + r.redrawn;
        let grids_before = counted(&self.reuse);
        let scope = Scope { fg, geometry };
        let outcome = if frame.met {
            // F = sqrt(D² − σ²) takes the grid's own error out of the difference: σ is the
            // estimate's raw reading there (a calibrated σ, larger, would hide the filter's
            // error), and F is then calibrated by the larger of the two factors.
            let mut reference = |timer: &mut StageTimer| -> Result<Option<Reference>> {
                let Some(grid) = self.ladder.cheapest_meeting(&last.at(), target * REFERENCE)
                else {
                    return Ok(None);
                };
                let (r, bound) = self.try_grid(fg, timer, geometry, grid)?;
                Ok(Some(Reference {
                    rmse: r.predicted_raw,
                    bound,
                    maps: r.maps,
                    record: r,
                }))
            };
            let accept = |p: f64, handed: bool| acceptable(filter_factor * p, target, handed);
            let rule = Against {
                met: Met {
                    rmse: last.predicted_raw,
                    ms: last.ms,
                },
                screen: target * SCREEN / filter_factor,
                accept: &accept,
                handed_on: handed.as_deref(),
            };
            filters.check(&scope, timer, rule, &mut reference)
        } else {
            // Out of reach: a candidate no worse than the grid, as far as the estimate can tell.
            let rule = OutOfReach {
                met: Met {
                    rmse: last.prediction.predicted_rmse,
                    ms: last.ms,
                },
                bound: &frame.search.bound,
                keep: KEEP,
                handed_on: handed.as_deref(),
            };
            filters.check_out_of_reach(&scope, timer, rule)
        };
        self.filters = filters;
        let outcome = outcome?;
        frame.maps += outcome.maps;
        let reference_maps = counted(&self.reuse) - grids_before;
        self.reuse.add(&ReuseCounts::all_rendered(
            outcome.maps.saturating_sub(reference_maps),
            fg.scene.render.shadow_map_size,
        ));
        if let Some((i, p, b)) = outcome.chosen {
            self.filter = Some(i);
            // Met: the filter's F. Out of reach, p is its difference from the grid, and the
            // filter is read as no worse than the grid's prediction, which stays.
            if frame.met {
                frame.predicted = filter_factor * p;
            } else {
                frame.difference = p;
            }
            frame.search.bound = b;
        }
        frame.filter_record = Some(FilterCheck {
            reference: outcome.reference,
            chosen: self.filter.map(|i| self.filters.label(i)),
            checks: outcome.checks,
            left_out: self.filters.left_out().to_vec(),
        });
        Ok(())
    }

    /// Out of reach: the line that says so, for the record's `warning`; the state's first such
    /// frame also hands it to the program (`progress::notice`: the binary prints it).
    fn out_of_reach(&mut self, frame: &Judged) -> Option<String> {
        if frame.met {
            return None;
        }
        let last = frame.last;
        let difference = frame.difference;
        let renders = self.filter.map_or(String::new(), |i| format!("; {} differs from that grid by {difference:.5} (RMS), within its predicted error, and is rendered instead", self.filters.label(i)));
        let line = format!(
            "auto: target RMSE {} is out of reach within n ≤ {} and {}² maps: the best predicted is {:.5} (regular:n={},layout=centred at {}² maps){renders}",
            self.method.target, self.method.max_n, self.method.max_size, last.prediction.predicted_rmse, last.n, last.map_size
        );
        if !self.warned {
            self.warned = true;
            crate::progress::notice(&line);
        }
        Some(line)
    }

    /// The frame's record (run.json's `method_record`).
    fn record(&self, frame: &Judged) -> AutoRecord {
        let last = frame.last;
        AutoRecord {
            method: record::TAG.into(),
            chosen: Chosen::centred((last.n, last.map_size)),
            target: self.method.target,
            // Met only where the prediction the frame reports is at most the target: a choice
            // kept within KEEP of it (a sequence's) is `kept`, not met.
            target_met: frame.predicted <= self.method.target as f64,
            tries: frame.search.tries.clone(),
            predicted_rmse: frame.predicted,
            predicted_sampling: last.prediction.predicted_sampling,
            predicted_map: last.prediction.predicted_map,
            certified: None,
            map_cost: self.map_cost(),
            filter: frame.filter_record.clone(),
            // What the frame renders: the grid stays in `chosen` as the reference it was judged by.
            renders: self.filter.map(|i| self.filters.label(i)),
            maps_rendered: frame.maps,
            estimated: true,
            kept: frame.kept,
            warning: frame.warning.clone(),
        }
    }

    /// How the search priced its maps, as the record keeps it.
    fn map_cost(&self) -> MapCost {
        MapCost {
            model: self.method.cost.name().into(),
            per_map: self
                .ladder
                .costs
                .0
                .iter()
                .map(|(z, c)| (z.to_string(), *c))
                .collect(),
            pricing_ms: self.pricing_ms,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
