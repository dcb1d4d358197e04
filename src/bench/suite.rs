//! `penumbra bench --suite seed-table2`: seed 000's Table 2 on this machine. For each of its four
//! scenes, adaptive (p_m = 0) and regular 17x17 in the same run, on the same device and settings:
//! one warm-up frame each, then `repeats` frames each, interleaved so that both see the same load;
//! the figure is the median wall-clock frame time (TimingMode::Frame: only the waits the method needs).

use super::errors::{self, ErrorColumns};
use super::seed::{SeedRow, TABLE2};
use super::stats::Summary;
use crate::frame::{self, FrameResult};
use crate::gpu::{AdapterSummary, GpuContext};
use crate::methods::Method;
use crate::scene::Scene;
use crate::timing::TimingMode;
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

pub struct SuiteOptions {
    pub repeats: u32,
    /// Folder holding `<scene>.toml` for each seed scene.
    pub scenes_dir: PathBuf,
    /// Asset cache for `cache:` meshes (`None`: the default cache).
    pub cache: Option<PathBuf>,
    pub adaptive: Method,
    pub regular: Method,
    /// Subset of the seed scenes, in the table's order; empty: all five (the bunny twice: close-up and seed framing).
    pub only: Vec<String>,
}

/// One method on one scene.
pub struct MethodResult {
    pub label: String,
    pub maps: u32,
    /// Every measured frame used the same number of maps (the method is deterministic).
    pub maps_stable: bool,
    pub frame_ms: Summary,
    /// Pipeline creation and upload before each frame (not in `frame_ms`).
    pub setup_ms: Summary,
    pub stages_ms: BTreeMap<String, Summary>,
    pub syncs: u32,
    pub errors: Option<ErrorColumns>,
}

impl MethodResult {
    pub fn fps(&self) -> f64 {
        1000.0 / self.frame_ms.median
    }
}

pub struct SceneResult {
    pub seed: &'static SeedRow,
    pub file: PathBuf,
    /// Screen width, height and shadow-map size the scene file sets.
    pub settings: [u32; 3],
    pub triangles: usize,
    pub geometry_pixels: usize,
    pub adaptive: MethodResult,
    pub regular: MethodResult,
}

impl SceneResult {
    /// As the seed states it: adaptive fps over regular fps (> 1: adaptive is faster).
    pub fn speedup(&self) -> f64 {
        self.regular.frame_ms.median / self.adaptive.frame_ms.median
    }
}

pub struct SuiteReport {
    pub adapter: AdapterSummary,
    pub timestamps_trusted: bool,
    pub repeats: u32,
    pub started_unix_s: u64,
    pub wall_s: f64,
    pub reference: Option<String>,
    pub scenes: Vec<SceneResult>,
}

/// Frames measured for one method: collected, then summarised.
#[derive(Default)]
struct Samples {
    frame_ms: Vec<f64>,
    setup_ms: Vec<f64>,
    stages_ms: BTreeMap<String, Vec<f64>>,
    maps: Vec<u32>,
    syncs: u32,
    errors: Option<ErrorColumns>,
}

impl Samples {
    fn add(&mut self, r: &FrameResult) {
        self.frame_ms.push(r.total_ms);
        self.setup_ms.push(r.stages_ms.get("setup").copied().unwrap_or(0.0));
        for (k, v) in r.stages_ms.iter().filter(|(k, _)| *k != "setup") {
            self.stages_ms.entry(k.clone()).or_default().push(*v);
        }
        self.maps.push(r.output.shadow_maps);
        self.syncs = r.output.syncs;
    }

    fn finish(self, method: &Method) -> Result<MethodResult> {
        let none = || Error::Param("bench: no frames measured (repeats must be at least 1)".into());
        Ok(MethodResult {
            label: method.label(),
            maps: *self.maps.first().ok_or_else(none)?,
            maps_stable: self.maps.windows(2).all(|w| w[0] == w[1]),
            frame_ms: Summary::of(&self.frame_ms).ok_or_else(none)?,
            setup_ms: Summary::of(&self.setup_ms).ok_or_else(none)?,
            stages_ms: self.stages_ms.iter().filter_map(|(k, v)| Some((k.clone(), Summary::of(v)?))).collect(),
            syncs: self.syncs,
            errors: self.errors,
        })
    }
}

/// The seed rows to run, in the table's order; an unknown name is an error that lists the known.
pub fn selected(only: &[String]) -> Result<Vec<&'static SeedRow>> {
    if let Some(bad) = only.iter().find(|n| !TABLE2.iter().any(|r| r.scene == n.as_str())) {
        let known: Vec<&str> = TABLE2.iter().map(|r| r.scene).collect();
        return Err(Error::Param(format!("bench: `{bad}` is not a seed-table2 scene (known: {})", known.join(", "))));
    }
    Ok(TABLE2.iter().filter(|r| only.is_empty() || only.iter().any(|n| n == r.scene)).collect())
}

/// A seed scene, loaded.
pub struct SuiteScene {
    pub seed: &'static SeedRow,
    pub file: PathBuf,
    pub scene: Scene,
}

/// Checks the options and loads every scene, before any GPU work: a missing asset or a typo fails
/// in a second, not after an hour of frames.
pub fn prepare(opts: &SuiteOptions) -> Result<Vec<SuiteScene>> {
    if opts.repeats == 0 {
        return Err(Error::Param("bench: --repeats must be at least 1".into()));
    }
    selected(&opts.only)?
        .into_iter()
        .map(|seed| {
            let file = opts.scenes_dir.join(format!("{}.toml", seed.scene));
            let scene = Scene::load_in(&file.to_string_lossy(), &[], opts.cache.as_deref())?;
            Ok(SuiteScene { seed, file, scene })
        })
        .collect()
}

/// Runs the suite on prepared scenes; `log` receives one line per frame (the bar shows the same).
pub fn run_seed_table2(ctx: &GpuContext, opts: &SuiteOptions, scenes: Vec<SuiteScene>, log: &mut dyn FnMut(&str)) -> Result<SuiteReport> {
    let started = Instant::now();
    let started_unix_s = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map(|d| d.as_secs()).unwrap_or(0);
    let frames = scenes.len() as u64 * 2 * (1 + opts.repeats as u64);
    let bar = crate::progress::bar(frames, "seed-table2");
    let mut results = Vec::new();
    let mut reference_label = None;
    for SuiteScene { seed: row, file, scene } in scenes {
        let methods = [&opts.adaptive, &opts.regular];
        let mut samples = [Samples::default(), Samples::default()];
        let mut reference = None;
        let mut geometry_pixels = 0;
        // Built once per scene: the repeats reuse pipelines and buffers.
        let mut renderers = [frame::Renderer::new(ctx, &scene, &opts.adaptive)?, frame::Renderer::new(ctx, &scene, &opts.regular)?];
        for repeat in 0..=opts.repeats {
            for (m, method) in methods.iter().enumerate() {
                bar.set_message(format!("{} {}", row.scene, method.name()));
                let r = renderers[m].frame(TimingMode::Frame)?;
                let what = if repeat == 0 { "warm-up".to_string() } else { format!("{repeat}/{}", opts.repeats) };
                let line = format!(
                    "{:7} {:18} {:8} {:>10.1} ms  {:>3} maps",
                    row.scene,
                    method.label(),
                    what,
                    r.total_ms,
                    r.output.shadow_maps
                );
                crate::progress::suspend(|| log(&line));
                bar.inc(1);
                if repeat == 0 {
                    // The warm-up's G-buffer is the same for both methods (same camera, same scene).
                    if m == 0 {
                        geometry_pixels = r.gbuffer.geometry_count();
                        reference = errors::reference(&scene, &r.gbuffer)?;
                        reference_label = reference.as_ref().map(|x| x.label.clone()).or(reference_label);
                    }
                    continue;
                }
                if let (Some(reference), None) = (&reference, &samples[m].errors) {
                    samples[m].errors = errors::errors(reference, &scene, &r)?;
                }
                samples[m].add(&r);
            }
        }
        let [a, r] = samples;
        results.push(SceneResult {
            seed: row,
            file,
            settings: [scene.render.width, scene.render.height, scene.render.shadow_map_size],
            triangles: scene.triangle_count(),
            geometry_pixels,
            adaptive: a.finish(&opts.adaptive)?,
            regular: r.finish(&opts.regular)?,
        });
    }
    bar.finish_and_clear();
    Ok(SuiteReport {
        adapter: ctx.summary.clone(),
        timestamps_trusted: ctx.timestamps_trusted,
        repeats: opts.repeats,
        started_unix_s,
        wall_s: started.elapsed().as_secs_f64(),
        reference: reference_label,
        scenes: results,
    })
}
