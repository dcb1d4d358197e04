//! The one measure loop of `compare`, `sweep` and `bench` (architecture.md, Timing): every
//! method gets one warm-up frame, then one frame in stages mode (a wait after every stage, so
//! each stage's wall time is known), then `repeats` frames in frame mode (only the waits the
//! method needs) whose median is the figure quoted. The last frame of each is handed to `judge`.
//!
//! Methods are measured in windows of [`WINDOW`]: a window's renderers are built, warmed up,
//! staged and timed interleaved round by round (so they see the same machine load), handed to
//! `after`, then dropped before the next window is built. Memory is that of one window whatever
//! the number of methods. What no method owns (scene upload, G-buffer targets and pass, shade and
//! raster passes) is detached from each finished renderer and carried into the next window's,
//! so a sweep builds it at most [`WINDOW`] times.

use crate::frame::{Detached, FrameOptions, FrameResult, Renderer};
use crate::gpu::stages::{outside_frame, Stage};
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::scene::Scene;
use crate::Result;
use std::collections::BTreeMap;

/// How long one method took, and what it did.
#[derive(Clone, Debug)]
pub struct Timing {
    /// Every frame-mode frame, in run order.
    pub totals_ms: Vec<f64>,
    pub median_ms: f64,
    pub min_ms: f64,
    pub max_ms: f64,
    /// Wall time per stage from the stages-mode frame, setup stages removed.
    pub stages_ms: BTreeMap<String, f64>,
    /// The method's per-frame reset before the frame's clock starts, on the stages-mode frame (the
    /// second on its renderer: pipelines and buffers were built for the warm-up).
    pub setup_ms: Option<f64>,
    /// Shadow maps of the last frame; `maps_stable`: every frame used the same number.
    pub shadow_maps: u32,
    pub maps_stable: bool,
    pub syncs: u32,
    /// `hardware` or `compute`: who rasterized the maps.
    pub raster: &'static str,
}

impl Timing {
    /// The timing of a method that was never measured (a failed setting's zeros).
    pub fn none() -> Timing {
        Timing {
            totals_ms: Vec::new(),
            median_ms: 0.0,
            min_ms: 0.0,
            max_ms: 0.0,
            stages_ms: BTreeMap::new(),
            setup_ms: None,
            shadow_maps: 0,
            maps_stable: true,
            syncs: 0,
            raster: "",
        }
    }
}

/// A measured method: its timing and what `judge` made of its last frame.
pub struct Measured<T> {
    pub timing: Timing,
    pub judged: T,
}

/// Which frame a progress callback is told about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    WarmUp,
    Stages,
    /// Timed frame `k` of `n` (from 1).
    Timed(u32, u32),
}

impl std::fmt::Display for Phase {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            Phase::WarmUp => write!(f, "warm-up"),
            Phase::Stages => write!(f, "stages"),
            Phase::Timed(k, n) => write!(f, "{k}/{n}"),
        }
    }
}

/// Frames the loop renders for `methods` methods.
pub fn frame_count(methods: usize, repeats: u32) -> u64 {
    methods as u64 * (2 + u64::from(repeats.max(1)))
}

/// Median of a non-empty list (mean of the middle two for an even count), from the statistics
/// helper; an empty list gives NaN, a figure no table mistakes for a time.
pub fn median(values: &[f64]) -> f64 {
    crate::record::stats::median(values).unwrap_or(f64::NAN)
}

/// Methods alive at once. Each holds its method state (an adaptive one at 64² held about 340 MB
/// on lavapipe), so this bounds a sweep's memory; within a window methods still share the machine
/// load round by round, and 4 is what a typical compare (a few baselines and an adaptive) fits.
pub const WINDOW: usize = 4;

/// A method's outcome: measured, or the one-line reason it failed (its renderer could not be
/// built, a frame or its judging returned an error). A failed method drops out of its window and
/// the others go on: a study records it as a failed row (robustness.md, "Failed settings").
pub type Outcome<T> = std::result::Result<Measured<T>, String>;

/// Runs the loop. `on_frame` sees every frame (logs, progress); `judge(i, frame)` gets the last
/// timed frame of method `i`, once, and may keep what it needs of it.
pub fn measure<T>(
    ctx: &GpuContext,
    scene: &Scene,
    methods: &[Method],
    repeats: u32,
    on_frame: &mut dyn FnMut(&Method, Phase, &FrameResult),
    judge: &mut dyn FnMut(usize, &FrameResult) -> Result<T>,
) -> Result<Vec<Outcome<T>>> {
    measure_with(
        ctx,
        scene,
        methods,
        repeats,
        on_frame,
        judge,
        &mut |_, _| Ok(()),
    )
}

/// As [`measure`]; `after(i, renderer)` gets method `i`'s renderer once its window's timed rounds
/// are done and before it is dropped, for untimed frames (compare's decision pictures).
/// Per-method errors become failed outcomes; only waiting for the device between windows fails
/// the whole loop.
pub fn measure_with<T>(
    ctx: &GpuContext,
    scene: &Scene,
    methods: &[Method],
    repeats: u32,
    on_frame: &mut dyn FnMut(&Method, Phase, &FrameResult),
    judge: &mut dyn FnMut(usize, &FrameResult) -> Result<T>,
    after: &mut dyn FnMut(usize, &mut Renderer) -> Result<()>,
) -> Result<Vec<Outcome<T>>> {
    measure_reusing(ctx, scene, methods, repeats, false, on_frame, judge, after)
}

/// As [`measure_with`], the renderers keeping their maps from frame to frame where `reuse`
/// (docs/reuse.md): on one still scene every frame after the warm-up keeps them all.
#[allow(clippy::too_many_arguments)]
pub fn measure_reusing<T>(
    ctx: &GpuContext,
    scene: &Scene,
    methods: &[Method],
    repeats: u32,
    reuse: bool,
    on_frame: &mut dyn FnMut(&Method, Phase, &FrameResult),
    judge: &mut dyn FnMut(usize, &FrameResult) -> Result<T>,
    after: &mut dyn FnMut(usize, &mut Renderer) -> Result<()>,
) -> Result<Vec<Outcome<T>>> {
    let mut out = Vec::with_capacity(methods.len());
    // What the finished renderers leave that any method can use (`Detached::attach_as`).
    let mut kept: Vec<Detached> = Vec::new();
    for (w, window) in methods.chunks(WINDOW).enumerate() {
        let first = w * WINDOW;
        let mut renderers: Vec<Slot<'_>> = Vec::with_capacity(window.len());
        for m in window {
            let built = match kept.pop() {
                Some(k) => k.attach_as(ctx, scene, m),
                None => Renderer::with_reuse(ctx, scene, m, reuse),
            };
            renderers.push(built.map_err(|e| e.to_string()));
        }
        let mut judge_window = |i: usize, f: &FrameResult| judge(first + i, f);
        let mut measured =
            measure_window(window, &mut renderers, repeats, on_frame, &mut judge_window);
        for (i, r) in renderers.iter_mut().enumerate() {
            if let (Ok(r), Ok(_)) = (r.as_mut(), &measured[i]) {
                if let Err(e) = after(first + i, r) {
                    measured[i] = Err(e.to_string());
                }
            }
        }
        out.extend(measured);
        kept.extend(
            renderers
                .into_iter()
                .filter_map(|r| r.ok())
                .map(Renderer::detach),
        );
        // wgpu frees dropped buffers and pipelines when the device is polled: before the next
        // window allocates, so the two never coexist.
        ctx.wait()?;
    }
    Ok(out)
}

/// A window's renderer, or why it failed (then it renders no more frames).
type Slot<'a> = std::result::Result<Renderer<'a>, String>;

/// A frame of slot `r`; an error fails the slot and returns None.
fn frame_of(r: &mut Slot<'_>, options: FrameOptions) -> Option<FrameResult> {
    let result = r.as_mut().ok()?.frame(options);
    match result {
        Ok(f) => Some(f),
        Err(e) => {
            *r = Err(e.to_string());
            None
        }
    }
}

/// One window: warm-up, stages and timed rounds, interleaved across its renderers; a renderer
/// that fails drops out, the others go on.
fn measure_window<T>(
    methods: &[Method],
    renderers: &mut [Slot<'_>],
    repeats: u32,
    on_frame: &mut dyn FnMut(&Method, Phase, &FrameResult),
    judge: &mut dyn FnMut(usize, &FrameResult) -> Result<T>,
) -> Vec<Outcome<T>> {
    let repeats = repeats.max(1);
    // Pipelines and buffers are built once per renderer (charged to the warm-up's setup) and every
    // later frame reuses them. No decision pictures: their read-backs would be timed, and nothing
    // here uses them.
    let options = |mode| FrameOptions {
        mode,
        pictures: false,
    };
    for (m, renderer) in methods.iter().zip(renderers.iter_mut()) {
        // warm-up: driver caches, allocator, build
        if let Some(r) = frame_of(renderer, options(TimingMode::Frame)) {
            on_frame(m, Phase::WarmUp, &r);
        }
    }
    let mut staged = Vec::with_capacity(methods.len());
    for (m, renderer) in methods.iter().zip(renderers.iter_mut()) {
        let Some(r) = frame_of(renderer, options(TimingMode::Stages)) else {
            staged.push((BTreeMap::new(), None));
            continue;
        };
        on_frame(m, Phase::Stages, &r);
        let mut stages = r.stages_ms;
        // `setup` (the method's per-frame reset; the build was the warm-up's) runs before the clock.
        let setup = stages.remove(Stage::SETUP.name);
        stages.retain(|k, _| !outside_frame(k));
        staged.push((stages, setup));
    }
    let mut totals: Vec<Vec<f64>> = vec![Vec::new(); methods.len()];
    let mut maps: Vec<Vec<u32>> = vec![Vec::new(); methods.len()];
    let mut syncs = vec![0; methods.len()];
    let mut raster = vec![""; methods.len()];
    let mut judged: Vec<Option<T>> = methods.iter().map(|_| None).collect();
    for k in 1..=repeats {
        for (i, m) in methods.iter().enumerate() {
            let Some(r) = frame_of(&mut renderers[i], options(TimingMode::Frame)) else {
                continue;
            };
            on_frame(m, Phase::Timed(k, repeats), &r);
            totals[i].push(r.total_ms);
            maps[i].push(r.output.shadow_maps);
            syncs[i] = r.output.syncs;
            raster[i] = r.raster.used;
            if k == repeats {
                match judge(i, &r) {
                    Ok(j) => judged[i] = Some(j),
                    Err(e) => renderers[i] = Err(e.to_string()),
                }
            }
        }
    }
    let mut out = Vec::with_capacity(methods.len());
    for (i, ((stages_ms, setup_ms), judged)) in staged.into_iter().zip(judged).enumerate() {
        let (judged, t) = match (&renderers[i], judged) {
            (Err(reason), _) => {
                out.push(Err(reason.clone()));
                continue;
            }
            (Ok(_), Some(j)) => (j, &totals[i]),
            (Ok(_), None) => {
                unreachable!("a renderer that never failed was judged on the last round")
            }
        };
        out.push(Ok(Measured {
            timing: Timing {
                median_ms: median(t),
                min_ms: t.iter().copied().fold(f64::INFINITY, f64::min),
                max_ms: t.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                totals_ms: t.clone(),
                stages_ms,
                setup_ms,
                shadow_maps: *maps[i].last().expect("at least one timed frame"),
                maps_stable: maps[i].windows(2).all(|w| w[0] == w[1]),
                syncs: syncs[i],
                raster: raster[i],
            },
            judged,
        }));
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn median_odd_and_even() {
        assert_eq!(super::median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(super::median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(super::median(&[7.0]), 7.0);
        assert_eq!(super::frame_count(3, 2), 12);
    }
}
