//! Shadow methods. Each one produces the same thing over the same G-buffer: a visibility image,
//! a count of shadow maps and a record, so every method lands on the same charts.
//!
//! A method is one module that implements [`ShadowMethod`] (its parameters) and [`MethodState`]
//! (its pipelines and buffers, built once per scene and settings), plus one line in [`REGISTRY`].
//! The frame driver (src/frame/) runs any of them without knowing which.

pub(crate) mod adaptive;
pub(crate) mod auto;
pub(crate) mod calibration;
pub(crate) mod cascades;
pub(crate) mod culled_maps;
pub(crate) mod environment;
pub(crate) mod estimate;
pub(crate) mod filtered;
pub(crate) mod fixed_samples;
pub(crate) mod hold;
pub(crate) mod hybrid_maps;
pub(crate) mod param_decl;
pub(crate) mod pcf;
pub(crate) mod pcss;
pub(crate) mod regions;
pub(crate) mod single_map;
pub(crate) mod sizes;
pub(crate) mod ssao;

pub use adaptive::params::{AdaptiveParams, Criterion, Scope, Weights};
pub use fixed_samples::Layout;
pub(crate) use param_decl::{ChoiceDecl, OptionalDecl, ParamDecl, SwitchDecl, WordDecl};

use crate::gpu::timing::StageTimer;
use crate::scene::LightKind;
use crate::stages::FrameGpu;
use crate::{Error, Result};
use std::any::Any;
use std::collections::BTreeMap;
use std::sync::Arc;

/// What a method hands back besides the visibility buffer it filled.
#[derive(Default)]
pub struct MethodOutput {
    pub shadow_maps: u32,
    /// CPU↔GPU synchronisations the algorithm needs (read-backs), not counting timing waits.
    pub syncs: u32,
    pub record: serde_json::Value,
    pub pictures: Vec<(String, image::RgbImage)>,
    /// The error estimate's per-pixel bound on |V − V_true| (`estimate = on`, `auto`), which the
    /// run files draw as `error-bound.png` and keep as `error-bound.exr`.
    pub bound: Option<Vec<f32>>,
}

/// A method's typed record (each method's own struct) as `MethodOutput.record` carries it.
pub(crate) fn record_value(
    method: &str,
    record: &impl serde::Serialize,
) -> Result<serde_json::Value> {
    serde_json::to_value(record).map_err(|e| Error::Limit(format!("{method}: its record: {e}")))
}

/// The families the charts and tables group methods by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    /// One map, one binary test per pixel.
    Hard,
    /// One map, filtered at lookup (percentage-closer filtering and its relatives).
    Pcf,
    /// One map turned into a prefiltered statistic (exponentials, moments, Fourier terms).
    Filtered,
    /// Many maps over the light (regular grid, adaptive).
    MultiSample,
    /// Lit by a panorama (`[environment]`): pixel lights, median-cut maps, ssao, the adaptive quadtree.
    Environment,
}

impl Family {
    pub fn title(self) -> &'static str {
        match self {
            Family::Hard => "hard",
            Family::Pcf => "pcf family (single map)",
            Family::Filtered => "filtered maps",
            Family::MultiSample => "multi-sample",
            Family::Environment => "environment",
        }
    }
    /// Family of a method name as rows store it; unknown names (older files) count as multi-sample.
    pub fn of_name(name: &str) -> Family {
        REGISTRY
            .iter()
            .find(|m| m.name == name)
            .map_or(Family::MultiSample, |m| m.family)
    }
}

/// One parameter as `penumbra methods` lists it.
pub struct Param {
    pub key: &'static str,
    pub default: &'static str,
    pub help: &'static str,
}

pub(crate) type ParamMap = BTreeMap<String, String>;

/// One registry line: a method's name, family, one-line summary, parameters and parser.
pub struct MethodInfo {
    pub name: &'static str,
    pub family: Family,
    pub summary: &'static str,
    pub params: &'static [Param],
    pub(crate) parse: fn(&ParamMap) -> Result<Arc<dyn ShadowMethod>>,
}

/// Every method, in the order `penumbra methods` lists them.
pub const REGISTRY: &[&MethodInfo] = &[
    &fixed_samples::HARD,
    &pcf::INFO,
    &pcss::INFO,
    &cascades::INFO,
    &filtered::ESM,
    &filtered::VSM,
    &filtered::EVSM,
    &filtered::MSM,
    &filtered::CSM,
    &fixed_samples::REGULAR,
    &adaptive::INFO,
    &auto::INFO,
    &regions::INFO,
    &environment::pixels::INFO,
    &environment::shadowmaps::INFO,
    &ssao::INFO,
    &environment::adaptive::INFO,
];

/// A method with its parameters fixed.
pub trait ShadowMethod: Send + Sync + Any {
    fn name(&self) -> &'static str;
    /// Short label for tables and charts: `adaptive:p_m=0,scope=local`.
    fn label(&self) -> String;
    /// Parameters as the run record states them (every parameter, defaults included).
    fn params_json(&self) -> serde_json::Value;
    /// Pipelines and buffers for this scene and settings: built once, reused by every frame.
    fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>>;
    fn as_any(&self) -> &dyn Any;
    /// The storage buffers it sizes by the screen, V among them, for the frame's size plan
    /// (`sizes::plan`, checked before anything is built): by default V alone, bound whole.
    fn size_needs(
        &self,
        scene: &crate::scene::Scene,
        limits: &wgpu::Limits,
    ) -> Vec<crate::gpu::size_plan::SizeNeed> {
        vec![sizes::visibility(scene, false, limits)]
    }
    /// The most plain shadow maps of the scene's `shadow_map_size` it keeps at once, before the
    /// budget splits them into arrays (`sizes::shadow_map_array`): a point light's sample counts its
    /// six cube faces. By default as many as the budget holds; 0 for a method without such maps.
    fn shadow_maps(&self, _scene: &crate::scene::Scene) -> u32 {
        u32::MAX
    }
    /// Why the method cannot run under a light of `kind` yet, or `None` when it can. By default a
    /// method places its samples on the rectangle (`Scene::light`), so it takes `rect` alone.
    fn unsupported_light(&self, kind: LightKind) -> Option<&'static str> {
        (kind != LightKind::Rect).then_some(ON_A_RECTANGLE)
    }
    /// Why the method cannot run a light of `kind` from maps of kind `maps`, where the light alone
    /// does not refuse it; checked with the light, before anything is built.
    fn unsupported_maps(
        &self,
        _kind: LightKind,
        _maps: crate::scene::MapKind,
    ) -> Option<&'static str> {
        None
    }
    /// Whether `build` times frames of the scene (auto's prices): the renderer then draws the
    /// screen (G-buffer and tile list) before building, so those frames shade what a frame shades.
    fn times_frames_at_build(&self) -> bool {
        false
    }
}

/// Why the many-sample methods refuse the other kinds (docs/lights.md, "Methods and kinds").
pub const ON_A_RECTANGLE: &str = "samples are placed on a rectangle";
/// Why the one-map methods refuse them.
pub const FROM_THE_CENTRE: &str =
    "its map looks from the rectangle's centre along the rectangle's normal";
/// Why pcss refuses them: its map, and the light size its search and filter scale with.
pub const PCSS_RECTANGLE: &str =
    "its map looks from the rectangle's centre and its search spans the rectangle's sides";

/// The kinds whose maps `Emitter::sample_map` makes: the rectangle, the disk and the spot
/// (perspective maps from points on the disk, or on the sphere's disk across the spot's axis) and
/// the sun (orthographic maps along directions in its cone).
pub(crate) fn maps_from_the_emitter(kind: LightKind) -> bool {
    matches!(
        kind,
        LightKind::Rect | LightKind::Disk | LightKind::Sun | LightKind::Spot
    )
}

/// The point light, whose samples `Emitter::sample_maps` makes as six cube faces each: hard, pcf,
/// pcss and regular shade them (docs/lights.md, "Cube maps for the point").
pub(crate) fn cube_maps(kind: LightKind) -> bool {
    kind == LightKind::Point
}
/// Maps per light sample: six cube faces for a point light, else one.
pub(crate) fn faces(scene: &crate::scene::Scene) -> u32 {
    if cube_maps(scene.emitter.kind()) {
        6
    } else {
        1
    }
}
/// Why adaptive refuses the point light.
pub(crate) const CUBE_MAPS_ARE_PLAIN: &str = "a point light's cube maps need maps = plain: the hybrid store keeps one map per lattice sample";
pub const ONE_MAP_PER_POINT: &str = "with scope = local or cull = on it keeps one map per light point, and a point light's sample is six cube faces (scope = global runs)";

/// Each method against the scene's light kind, before anything is built, traced or written.
pub fn check_lights(scene: &crate::scene::Scene, methods: &[Method]) -> Result<()> {
    methods.iter().try_for_each(|m| m.check_light(scene))
}

/// A built method. `reset` runs before the frame's clock starts (zero fills); `run` is the frame.
/// `Send`, so a renderer moves to the thread that renders with it (Python releases the GIL then).
pub trait MethodState: Send {
    fn reset(&mut self, fg: &FrameGpu) -> Result<()>;
    /// `pictures`: read back what the decision pictures need. A per-frame request (timed runs turn
    /// it off), so it is an argument, not part of the shared [`FrameGpu`].
    fn run(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        pictures: bool,
    ) -> Result<MethodOutput>;
    /// After the frame's clock stopped (V is read back): a method whose frame needed no read-back
    /// reads its record here (decisions, maps used, pictures), outside the timed frame.
    fn finish(&mut self, _fg: &FrameGpu, _out: &mut MethodOutput) -> Result<()> {
        Ok(())
    }
    /// After a frame that failed with an overflow of a list the method sizes itself: enlarge it so
    /// that the frame can run again (the renderer then does). False when nothing can grow: the
    /// overflow is the frame's error. The default has no such list.
    fn grow(&mut self, _fg: &FrameGpu) -> Result<bool> {
        Ok(false)
    }
    /// What a state decided that the same method's next state should start from when a renderer
    /// moves to the next frame of a sequence (its state is built again): auto's choice.
    fn memory(&self) -> Option<serde_json::Value> {
        None
    }
    /// Takes over what `memory` gave, before the first frame.
    fn recall(&mut self, _memory: &serde_json::Value) {}
    /// The renderer's camera moved (`Renderer::set_camera`): what a state kept about the last
    /// frame's pixels no longer holds (auto's settled choice).
    fn camera_moved(&mut self) {}
    /// Tests: from the next frame on, keep what a frame overwrites as it goes (each chunk's maps,
    /// each level's buffers) for `inspect`. It adds read-backs, so only the methods whose buffers
    /// do not outlive the frame implement it.
    fn keep_intermediates(&mut self) {}
    /// After a frame (tests, benches): the maps and intermediate buffers the CPU twins compare,
    /// read back from what the state holds; `Renderer::inspect` downcasts it to the method's type.
    fn inspect(&mut self, _fg: &FrameGpu) -> Result<Option<Box<dyn Any>>> {
        Ok(None)
    }
    /// The screen-sized buffers it created, by label, as `ShadowMethod::size_needs` plans them
    /// (tests check the two agree).
    fn buffer_sizes(&self) -> Vec<(String, u64)> {
        Vec::new()
    }
    /// The last frame's maps rendered, kept and partly drawn again (docs/reuse.md); None for a
    /// method that keeps none (every map rendered).
    fn reuse(&self) -> Option<crate::render::kept_maps::ReuseCounts> {
        None
    }
    /// The maps it keeps, handed to the renderer when the state is dropped (the next frame's state
    /// takes them from `FrameGpu::maps_kept`).
    fn release_maps(&mut self) -> Vec<crate::render::kept_maps::KeptMaps> {
        Vec::new()
    }
}

/// A parsed method spec: cheap to clone, compared by label.
#[derive(Clone)]
pub struct Method(Arc<dyn ShadowMethod>);

impl std::fmt::Debug for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.label())
    }
}

impl PartialEq for Method {
    fn eq(&self, other: &Self) -> bool {
        self.label() == other.label()
    }
}

/// The methods that take parameter `key`, in registry order (the CLI's `--set` names them when a
/// method parameter is given as a render setting).
pub fn methods_with_param(key: &str) -> Vec<&'static str> {
    REGISTRY
        .iter()
        .filter(|m| m.params.iter().any(|p| p.key == key))
        .map(|m| m.name)
        .collect()
}

impl Method {
    /// `name` or `name:key=value,key=value`, plus `extra` pairs (`penumbra render --param`).
    pub fn parse(spec: &str, extra: &[(String, String)]) -> Result<Method> {
        let (name, inline) = match spec.split_once(':') {
            Some((n, rest)) => (n, rest),
            None => (spec, ""),
        };
        let mut params = BTreeMap::new();
        for pair in inline.split(',').filter(|s| !s.is_empty()) {
            let (k, v) = pair.split_once('=').ok_or_else(|| {
                Error::Param(format!("method `{spec}`: `{pair}` is not key=value"))
            })?;
            if let Some(first) = params.insert(k.trim().to_string(), v.trim().to_string()) {
                return Err(Error::Param(format!(
                    "method `{spec}`: `{}` is given twice ({first} and {})",
                    k.trim(),
                    v.trim()
                )));
            }
        }
        for (k, v) in extra {
            if let Some(first) = params.insert(k.clone(), v.clone()) {
                return Err(Error::ParamTwice {
                    spec: spec.to_string(),
                    key: k.clone(),
                    first,
                    again: v.clone(),
                });
            }
        }
        let info = REGISTRY.iter().find(|m| m.name == name).ok_or_else(|| {
            let known: Vec<&str> = REGISTRY.iter().map(|m| m.name).collect();
            Error::Param(format!(
                "unknown method `{name}` (known: {})",
                known.join(", ")
            ))
        })?;
        if let Some(k) = params
            .keys()
            .find(|k| !info.params.iter().any(|p| p.key == k.as_str()))
        {
            let allowed: Vec<&str> = info.params.iter().map(|p| p.key).collect();
            return Err(Error::Param(format!(
                "method `{name}` has no parameter `{k}` (its parameters: {})",
                if allowed.is_empty() {
                    "none".to_string()
                } else {
                    allowed.join(", ")
                }
            )));
        }
        // Every message names the method: `pcf: parameter kernel = `foo`: ...`.
        (info.parse)(&params).map(Method).map_err(|e| match e {
            Error::Param(m) if !m.starts_with(name) => Error::Param(format!("{name}: {m}")),
            e => e,
        })
    }

    pub fn new(m: impl ShadowMethod) -> Method {
        Method(Arc::new(m))
    }
    pub fn hard() -> Method {
        Method::new(fixed_samples::Fixed::Hard)
    }
    /// The regular grid on the N×N lattice, corners included.
    pub fn regular(n: u32) -> Method {
        Method::new(fixed_samples::Fixed::Regular {
            n,
            layout: Layout::Lattice,
            cull: false,
            estimate: false,
        })
    }
    pub fn adaptive(p: AdaptiveParams) -> Method {
        Method::new(adaptive::Adaptive(p))
    }

    pub fn name(&self) -> &'static str {
        self.0.name()
    }
    pub fn params_json(&self) -> serde_json::Value {
        self.0.params_json()
    }
    pub fn label(&self) -> String {
        self.0.label()
    }
    pub fn family(&self) -> Family {
        Family::of_name(self.name())
    }
    /// `ShadowMethod::times_frames_at_build`.
    pub(crate) fn times_frames_at_build(&self) -> bool {
        self.0.times_frames_at_build()
    }
    pub(crate) fn build(&self, fg: &FrameGpu) -> Result<Box<dyn MethodState>> {
        self.check_light(fg.scene)?;
        self.0.build(fg)
    }
    /// `regular: light kind `disk` is not supported yet (samples are placed on a rectangle)`.
    pub fn check_light(&self, scene: &crate::scene::Scene) -> Result<()> {
        let kind = scene.emitter.kind();
        if let Some(why) = self.0.unsupported_light(kind) {
            return Err(Error::Param(format!("{}: light kind `{}` is not supported yet ({why}); scene {} (docs/lights.md lists the pairs)", self.name(), kind.name(), scene.origin)));
        }
        // The maps, not the light, refuse it: name the setting (`--set maps=hybrid`).
        match self.0.unsupported_maps(kind, scene.render.maps) {
            None => Ok(()),
            Some(why) => Err(Error::Param(format!(
                "{}: maps = {} is not supported{} ({why}); scene {} (use maps = plain)",
                self.name(),
                if scene.render.maps == crate::scene::MapKind::Hybrid {
                    "hybrid"
                } else {
                    "plain"
                },
                if kind == LightKind::Rect {
                    String::new()
                } else {
                    format!(" with light kind `{}`", kind.name())
                },
                scene.origin
            ))),
        }
    }
    /// The method's own type, for callers that need its parameters (`as_any().downcast_ref`).
    pub fn as_any(&self) -> &dyn Any {
        self.0.as_any()
    }
    /// The adaptive parameters, when this is the adaptive method.
    pub fn adaptive_params(&self) -> Option<&AdaptiveParams> {
        self.as_any()
            .downcast_ref::<adaptive::Adaptive>()
            .map(|a| &a.0)
    }
}

pub(crate) fn get_u32(params: &ParamMap, key: &str, default: u32) -> Result<u32> {
    match params.get(key) {
        None => Ok(default),
        Some(v) => v.parse().map_err(|_| {
            Error::Param(format!(
                "parameter {key} = `{v}` is not a non-negative integer"
            ))
        }),
    }
}

/// Parameter helpers shared by the methods' parsers.
pub(crate) fn get_f32(params: &ParamMap, key: &str, default: f32) -> Result<f32> {
    match params.get(key) {
        None => Ok(default),
        Some(v) => match v.parse::<f32>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(Error::Param(format!(
                "parameter {key} = `{v}` is not a finite number"
            ))),
        },
    }
}

/// `value` in `lo..=hi`, or a message naming the method, key and value.
pub(crate) fn check_range<T: PartialOrd + std::fmt::Display>(
    method: &str,
    key: &str,
    value: T,
    lo: T,
    hi: T,
) -> Result<T> {
    if value < lo || value > hi {
        return Err(Error::Param(format!(
            "{method}: {key} = {value} is outside {lo}..={hi}"
        )));
    }
    Ok(value)
}

/// Label `name:k=v,...` from the parameters that differ from their defaults (registry order).
pub(crate) fn label_from(info: &MethodInfo, values: &[(&str, String)]) -> String {
    let mut parts = Vec::new();
    for p in info.params {
        if let Some((_, v)) = values.iter().find(|(k, _)| *k == p.key) {
            if v != p.default {
                parts.push(format!("{}={v}", p.key));
            }
        }
    }
    if parts.is_empty() {
        info.name.to_string()
    } else {
        format!("{}:{}", info.name, parts.join(","))
    }
}
