//! `penumbra bench --suite seed-table2`: seed 000's Table 2 on this machine. For each of its four
//! scenes, adaptive (p_m = 0), regular 17x17 and the fair grid (centred, about the adaptive run's
//! map count: fair.rs) in the same run, on the same device and settings: one warm-up frame each,
//! then `repeats` frames each, interleaved so that all see the same load; with them, where asked,
//! the per-region method (`regions`), set against both grids (table.rs);
//! the figure is the median wall-clock frame time (TimingMode::Frame: only the waits the method needs).

use super::errors::ErrorColumns;
use super::fair;
use super::seed::{SeedRow, TABLE2};
use crate::gpu::{AdapterSummary, GpuContext};
use crate::methods::Method;
use crate::record::judge::Judge;
use crate::record::measure::{self, Measured, Phase};
use crate::record::stats::Summary;
use crate::record::{self, Provenance, RunInfo};
use crate::reference::truth::{self, Cache};
use crate::reference::ReferenceMode;
use crate::report::charts::ResultRow;
use crate::scene::Scene;
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
    /// The per-region method timed beside them (`--regions`; `None`: left out).
    pub regions: Option<Method>,
    /// Subset of the seed scenes, in the table's order; empty: all five (the bunny twice: close-up and seed framing).
    pub only: Vec<String>,
    /// Render settings set over every scene file (`--set raster=auto`), as (key, value).
    pub sets: Vec<(String, String)>,
    /// Each method keeps its maps from frame to frame (`--reuse on`): the timed frames of a still
    /// scene then rasterize nothing (docs/reuse.md).
    pub reuse: bool,
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
    /// The row `results.jsonl` holds for this method (the schema `compare` writes).
    pub row: ResultRow,
    /// The method failed at run time: why (its figures are zero; the tables say "failed: reason").
    pub failed: Option<String>,
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
    /// The centred grid with N² nearest to `probe_maps` (fair::grid_n).
    pub fair: MethodResult,
    /// The per-region method, where the suite ran one.
    pub regions: Option<MethodResult>,
    /// The adaptive method's map count in one untimed frame before the measured ones.
    pub probe_maps: u32,
}

impl SceneResult {
    /// As the seed states it: adaptive fps over regular fps (> 1: adaptive is faster).
    pub fn speedup(&self) -> f64 {
        self.regular.frame_ms.median / self.adaptive.frame_ms.median
    }

    /// The same ratio against the fair grid.
    pub fn fair_speedup(&self) -> f64 {
        self.fair.frame_ms.median / self.adaptive.frame_ms.median
    }

    /// Every method measured on the scene, in the table's order.
    pub fn methods(&self) -> Vec<&MethodResult> {
        [&self.adaptive, &self.regular, &self.fair]
            .into_iter()
            .chain(&self.regions)
            .collect()
    }

    /// The timed adaptive frames used the map count the fair grid was chosen from.
    pub fn probe_held(&self) -> bool {
        self.adaptive.maps_stable && self.adaptive.maps == self.probe_maps
    }
}

/// One run of a suite: every scene's adaptive, regular and fair-grid results.
pub struct SuiteResults {
    pub adapter: AdapterSummary,
    pub timestamps_trusted: bool,
    pub repeats: u32,
    pub started_unix_s: u64,
    pub wall_s: f64,
    pub reference: Option<String>,
    pub scenes: Vec<SceneResult>,
    /// The `--set` overrides, `key=value`, written under the table beside the scene files.
    pub sets: Vec<String>,
}

impl SuiteResults {
    /// One report row per scene and method, adaptive, lattice, fair grid (the record layer's rows,
    /// one schema with `compare`), so `report.html` shows its tables and charts like `compare` does.
    pub fn rows(&self) -> Vec<ResultRow> {
        self.scenes
            .iter()
            .flat_map(|s| s.methods().into_iter().map(|m| m.row.clone()))
            .collect()
    }
}

impl MethodResult {
    fn from_measured(m: Measured<crate::metrics::Metrics>, row: ResultRow) -> MethodResult {
        let t = m.timing;
        let one = |v: f64| Summary {
            median: v,
            min: v,
            max: v,
            samples: vec![v],
        };
        MethodResult {
            label: row.label.clone(),
            maps: t.shadow_maps,
            maps_stable: t.maps_stable,
            frame_ms: Summary {
                median: t.median_ms,
                min: t.min_ms,
                max: t.max_ms,
                samples: t.totals_ms.clone(),
            },
            setup_ms: one(t.setup_ms.unwrap_or(0.0)),
            stages_ms: t
                .stages_ms
                .iter()
                .map(|(k, v)| (k.clone(), one(*v)))
                .collect(),
            syncs: t.syncs,
            errors: Some(ErrorColumns::of(&m.judged)),
            row,
            failed: None,
        }
    }

    /// A method that failed: its row says why.
    fn from_failed(row: ResultRow) -> MethodResult {
        let zero = Summary {
            median: 0.0,
            min: 0.0,
            max: 0.0,
            samples: Vec::new(),
        };
        MethodResult {
            label: row.label.clone(),
            maps: 0,
            maps_stable: true,
            frame_ms: zero.clone(),
            setup_ms: zero,
            stages_ms: BTreeMap::new(),
            syncs: 0,
            errors: None,
            failed: row.failed.clone(),
            row,
        }
    }
}

/// The seed rows to run, in the table's order; an unknown name is an error that lists the known.
pub fn selected(only: &[String]) -> Result<Vec<&'static SeedRow>> {
    if let Some(bad) = only
        .iter()
        .find(|n| !TABLE2.iter().any(|r| r.scene == n.as_str()))
    {
        let known: Vec<&str> = TABLE2.iter().map(|r| r.scene).collect();
        return Err(Error::param(format!(
            "bench: `{bad}` is not a seed-table2 scene (known: {})",
            known.join(", ")
        )));
    }
    Ok(TABLE2
        .iter()
        .filter(|r| only.is_empty() || only.iter().any(|n| n == r.scene))
        .collect())
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
        return Err(Error::param("bench: --repeats must be at least 1".into()));
    }
    selected(&opts.only)?
        .into_iter()
        .map(|seed| {
            let file = opts.scenes_dir.join(format!("{}.toml", seed.scene));
            let scene = Scene::load_in(&file.to_string_lossy(), &opts.sets, opts.cache.as_deref())?;
            Ok(SuiteScene { seed, file, scene })
        })
        .collect()
}

/// The ground truth of the suite's error columns (method.md §5: 32x32 stratified jitter, fixed
/// seed, CPU BVH), cached on disk.
pub const REFERENCE: ReferenceMode = ReferenceMode::DEFAULT_CONTINUOUS;

/// Runs the suite on prepared scenes through the record layer (`record::measure`, one warm-up
/// and one stages-mode frame per method, then `repeats` timed frames, the three methods
/// interleaved), after one untimed adaptive frame that picks the fair grid; `log` receives one
/// line per frame (the bar shows the same).
pub fn run_seed_table2(
    ctx: &GpuContext,
    opts: &SuiteOptions,
    scenes: Vec<SuiteScene>,
    log: &mut dyn FnMut(&str),
) -> Result<SuiteResults> {
    let started = Instant::now();
    let started_unix_s = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    let bar = crate::progress::bar(
        scenes.len() as u64 * (1 + measure::frame_count(3, opts.repeats)),
        "seed-table2",
    );
    let reference_label = format!("{}, CPU BVH", truth::mode_label(&REFERENCE));
    let mut results = Vec::new();
    for SuiteScene {
        seed: row,
        file,
        scene,
    } in scenes
    {
        // The probe picks the fair grid; where the adaptive method fails, so does its fair grid
        // (no map count to match), and both are failed rows.
        let probe = crate::frame::render(
            ctx,
            &scene,
            &opts.adaptive,
            crate::gpu::timing::TimingMode::Frame,
        )
        .map_err(|e| e.to_string());
        let probe_maps = probe.as_ref().map_or(0, |p| p.output.shadow_maps);
        bar.inc(1);
        match &probe {
            Ok(_) => crate::progress::suspend(|| {
                log(&format!(
                    "{:7} {:18} {:8} {:>3} maps: fair grid {}",
                    row.scene,
                    opts.adaptive.label(),
                    "probe",
                    probe_maps,
                    fair::grid_method(probe_maps)
                ))
            }),
            Err(e) => crate::progress::suspend(|| {
                log(&crate::record::failed_line(
                    &format!("{} {}", row.scene, opts.adaptive.label()),
                    e,
                ))
            }),
        }
        let mut methods = vec![opts.adaptive.clone(), opts.regular.clone()];
        if probe.is_ok() {
            methods.push(Method::parse(&fair::grid_method(probe_maps), &[])?);
        }
        methods.extend(opts.regions.clone());
        let (g, reference) = truth::for_scene(ctx, &scene, REFERENCE, &Cache::default_for(false))?;
        let judge = Judge::new(&scene, &g, reference.values);
        let mut on_frame = |method: &Method, phase: Phase, r: &crate::frame::FrameResult| {
            bar.set_message(format!("{} {}", row.scene, method.name()));
            let line = format!(
                "{:7} {:18} {:8} {:>10.1} ms  {:>3} maps ({} rendered, {} kept)",
                row.scene,
                method.label(),
                phase.to_string(),
                r.total_ms,
                r.output.shadow_maps,
                r.reuse.rendered,
                r.reuse.kept
            );
            crate::progress::suspend(|| log(&line));
            bar.inc(1);
        };
        let mut judge_frame = |i: usize, f: &crate::frame::FrameResult| {
            Ok(judge.judge(&scene, &methods[i].label(), f)?.metrics)
        };
        let measured = measure::measure_reusing(
            ctx,
            &scene,
            &methods,
            opts.repeats,
            opts.reuse,
            &mut on_frame,
            &mut judge_frame,
            &mut |_, _| Ok(()),
        )?;
        let info = RunInfo {
            scene: row.scene,
            resolution: [scene.render.width, scene.render.height],
            shadow_map_size: scene.render.shadow_map_size,
            adapter: &ctx.summary,
            reference: reference_label.clone(),
            repeats: opts.repeats,
        };
        let provenance =
            Provenance::of_scene("bench seed-table2", &scene, &[], opts.cache.as_deref());
        let mut done = measured
            .into_iter()
            .zip(&methods)
            .map(|(m, method)| match m {
                Ok(m) => {
                    let r = record::row(
                        &info,
                        method,
                        &m.timing,
                        m.judged.clone(),
                        BTreeMap::new(),
                        provenance.clone(),
                    );
                    MethodResult::from_measured(m, r)
                }
                Err(reason) => {
                    crate::progress::suspend(|| {
                        log(&record::failed_line(
                            &format!("{} {}", row.scene, method.label()),
                            &reason,
                        ))
                    });
                    MethodResult::from_failed(record::failed_row(
                        &info,
                        method,
                        &reason,
                        provenance.clone(),
                    ))
                }
            });
        let (Some(adaptive), Some(regular)) = (done.next(), done.next()) else {
            return Err(Error::param("bench: no frames measured".into()));
        };
        let fair = match (probe.is_ok().then(|| done.next()).flatten(), &probe) {
            (Some(fair), _) => fair,
            (None, probe) => {
                let reason = format!(
                    "no fair grid: the adaptive probe frame failed ({})",
                    probe.as_ref().err().map_or("", String::as_str)
                );
                let grid = Method::parse("regular:n=2,layout=centred", &[])?;
                let mut r = record::failed_row(&info, &grid, &reason, provenance.clone());
                r.label = "fair grid".into();
                MethodResult::from_failed(r)
            }
        };
        results.push(SceneResult {
            seed: row,
            file,
            settings: [
                scene.render.width,
                scene.render.height,
                scene.render.shadow_map_size,
            ],
            triangles: scene.triangle_count(),
            geometry_pixels: judge.geometry_pixels(),
            adaptive,
            regular,
            fair,
            regions: done.next(),
            probe_maps,
        });
    }
    bar.finish_and_clear();
    let rows: Vec<&MethodResult> = results.iter().flat_map(SceneResult::methods).collect();
    if let Some(line) = record::failed_summary(
        rows.iter().filter(|m| m.failed.is_some()).count(),
        rows.len(),
    ) {
        crate::progress::suspend(|| log(&line));
    }
    Ok(SuiteResults {
        adapter: ctx.summary.clone(),
        timestamps_trusted: ctx.timestamps_trusted,
        repeats: opts.repeats,
        started_unix_s,
        wall_s: started.elapsed().as_secs_f64(),
        reference: Some(reference_label),
        scenes: results,
        sets: opts.sets.iter().map(|(k, v)| format!("{k}={v}")).collect(),
    })
}
