//! `penumbra sequence`: N frames of a scene whose light, camera or one mesh moves along a path
//! (`path`), every method rendered in every frame and judged against that frame's own CPU
//! reference (`ground_truth`, cached). Besides each frame's error it measures how well a method's
//! frame-to-frame change follows the reference's, and how many pixels pop (`temporal`,
//! docs/sequence.md). Writes per-frame rows, per-method summaries, charts, animations (APNG) and a
//! self-contained report; everything is encoded in memory before the first file is written.

pub(crate) mod apng;
pub mod command;
pub mod path;
pub(crate) mod section;
pub mod tables;
pub(crate) mod temporal;

use crate::frame::{Detached, FrameOptions, Renderer};
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::metrics::{self, abs_error_image, Metrics};
use crate::record::measure::median;
use crate::record::run_files;
use crate::record::RowCore;
use crate::reference::truth::{self, Cache};
use crate::reference::ReferenceMode;
use crate::render::kept_maps::ReuseCounts;
use crate::report::charts::{self, svg_to_png, FrameSeries};
use crate::scene::Scene;
use crate::studies::compare::ERROR_SCALE;
use crate::{progress, Error, Result};
use path::Animation;
use serde::{Deserialize, Serialize};
use temporal::{FramePair, SequenceTemporal};

/// Most frames a sequence may have (every frame costs a CPU reference).
pub const MAX_FRAMES: u32 = 1000;
/// How long each animation frame is shown.
pub const FRAME_DELAY_MS: u16 = 125;

pub struct SequenceJob<'a> {
    pub scene: &'a Scene,
    pub methods: Vec<Method>,
    pub frames: u32,
    pub animation: Animation,
    pub reference: ReferenceMode,
    pub cache: Cache,
    /// Whether each method keeps its shadow maps from frame to frame (docs/reuse.md).
    pub reuse: Reuse,
    /// `Frame` (the frame's wall clock alone) or `Stages` (a wait after every stage: each row
    /// gets its stages' wall clock, `stages_ms`).
    pub timing: TimingMode,
}

/// `--reuse`: every method keeps the maps that nothing moved (`on`), renders all (`off`), or
/// runs twice, without and with, side by side in each frame (`both`: the rows say which, and each
/// reuse frame's V is compared bit for bit with the frame without).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Reuse {
    On,
    Off,
    Both,
}

impl Reuse {
    pub fn parse(v: &str) -> Result<Reuse> {
        match v {
            "on" => Ok(Reuse::On),
            "off" => Ok(Reuse::Off),
            "both" => Ok(Reuse::Both),
            _ => Err(Error::param(format!("--reuse {v}: use on, off or both"))),
        }
    }

    /// Each method's runs, in the order a frame renders them: (reuse, the run's label).
    fn runs(self, label: &str) -> Vec<(bool, String)> {
        match self {
            Reuse::On => vec![(true, label.to_string())],
            Reuse::Off => vec![(false, label.to_string())],
            Reuse::Both => vec![
                (false, format!("{label} (reuse off)")),
                (true, format!("{label} (reuse on)")),
            ],
        }
    }
}

/// One method in one frame: a line of `frames.jsonl`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameRow {
    /// Scene, the label as spec, method, params, maps, map size, RMSE, the wall clock of this one
    /// frame in frame mode (no repeats, pipelines built before the clock), adapter, build.
    #[serde(flatten)]
    pub core: RowCore,
    pub label: String,
    pub frame: u32,
    pub metrics: Metrics,
    /// Against the frame before; `None` in frame 0.
    pub temporal: Option<FramePair>,
    pub light_center: [f32; 3],
    pub camera_eye: [f32; 3],
    /// The run kept its maps from frame to frame (docs/reuse.md).
    #[serde(default)]
    pub reuse: bool,
    /// Maps rendered, kept and partly drawn again this frame, and the texels rasterized.
    #[serde(default)]
    pub reuse_counts: ReuseCounts,
    /// `--reuse both`, a reuse run's frame: V equal bit for bit to the same frame without reuse.
    #[serde(default)]
    pub v_equal_without_reuse: Option<bool>,
    /// Bytes of shadow maps the renderer keeps for the next frame (at most the map budget).
    #[serde(default)]
    pub kept_bytes: u64,
    /// `--timing stages`: each stage's wall clock in this frame, and `attach`, the renderer's
    /// move to this frame's scene before its clock (the mesh's upload, what moved); empty otherwise.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub stages_ms: std::collections::BTreeMap<String, f64>,
}

/// One method over the whole sequence: a line of `summary.json`'s `methods`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodSummary {
    pub label: String,
    pub method: String,
    pub frames: u32,
    /// Mean over frames of the per-frame RMSE of V.
    pub mean_rmse: f64,
    /// Mean over frames of the per-frame share of pixels off by more than 1/32.
    pub mean_bad_pixel_share: f64,
    pub temporal: SequenceTemporal,
    pub maps_mean: f64,
    pub maps_min: u32,
    pub maps_max: u32,
    /// Median over frames of the frame's wall clock.
    pub median_ms: f64,
    /// The frame with the most popping pixels, and how many.
    pub worst_pop_frame: Option<(u32, u64)>,
    /// The run kept its maps from frame to frame.
    #[serde(default)]
    pub reuse: bool,
    /// Mean over the frames after the first: the wall clock, maps rendered whole, maps kept, and
    /// texels rasterized over the texels of the maps used.
    #[serde(default)]
    pub mean_ms_after_first: f64,
    #[serde(default)]
    pub rendered_mean_after_first: f64,
    #[serde(default)]
    pub kept_mean_after_first: f64,
    #[serde(default)]
    pub texel_share_after_first: f64,
    /// `--reuse both`, a reuse run: (frames whose V equals the frame without reuse bit for bit,
    /// frames compared).
    #[serde(default)]
    pub v_equal_frames: Option<(u32, u32)>,
    /// `--reuse both`, a reuse run: the median over the frames after the first of its frame time
    /// over the same method's without reuse in the same frame (below 1: reuse is faster). Each
    /// pair ran back to back, so a load spike on a shared machine moves both.
    #[serde(default)]
    pub time_ratio_to_without_reuse: Option<f64>,
    /// Median over the frames after the first of the wall clock.
    #[serde(default)]
    pub median_ms_after_first: f64,
    /// The most bytes of maps kept between two frames.
    #[serde(default)]
    pub kept_bytes_max: u64,
}

pub struct SequenceOutcome {
    pub scene: String,
    pub title: String,
    pub description: String,
    pub resolution: [u32; 2],
    pub reference: String,
    pub adapter: String,
    pub rows: Vec<FrameRow>,
    pub summaries: Vec<MethodSummary>,
    /// (file stem, caption, SVG) of each chart.
    pub charts: Vec<(String, String, String)>,
    /// (caption, APNG bytes): the reference first, then every method.
    pub animations: Vec<(String, Vec<u8>)>,
    /// Every output file but the report: (path relative to the output folder, bytes).
    pub files: Vec<(String, Vec<u8>)>,
}

/// The job's own checks, before the GPU starts (`run` makes them too). Every frame's scene goes
/// through the scene file's light checks (`scene::light_checks`): a moved light, camera or mesh
/// can make a light that the file would have been refused for.
pub fn check(job: &SequenceJob) -> Result<()> {
    if job.frames < 2 || job.frames > MAX_FRAMES {
        return Err(Error::param(format!(
            "--frames {}: a sequence needs 2..={MAX_FRAMES} frames",
            job.frames
        )));
    }
    if job.methods.is_empty() {
        return Err(Error::param("--methods: no method given".into()));
    }
    for i in 0..job.frames {
        let scene_t = job.animation.frame(job.scene, i, job.frames);
        if let Err(e) = crate::scene::light_checks::check_scene(&scene_t) {
            let light = scene_t.light.center.to_array();
            return Err(Error::param(format!(
                "--animate: frame {} of {} ({}, the light's centre at {light:?}): {e}",
                i + 1,
                job.frames,
                job.animation.describe(job.scene)
            )));
        }
    }
    Ok(())
}

/// Runs the job; `log` gets one line per finished frame.
pub fn run(ctx: &GpuContext, job: &SequenceJob, log: &dyn Fn(&str)) -> Result<SequenceOutcome> {
    check(job)?;
    let scene = job.scene;
    let (w, h) = (scene.render.width, scene.render.height);
    // Each method's runs (one, or without and with reuse), in the order every frame renders them.
    let runs: Vec<(usize, bool, String)> = job
        .methods
        .iter()
        .enumerate()
        .flat_map(|(k, m)| {
            job.reuse
                .runs(&m.label())
                .into_iter()
                .map(move |(r, l)| (k, r, l))
        })
        .collect();
    let n = runs.len();
    let adapter =
        serde_json::Value::from(format!("{} ({})", ctx.summary.name, ctx.summary.backend));
    let mut rows: Vec<FrameRow> = Vec::new();
    let mut method_frames: Vec<Vec<image::RgbImage>> = vec![Vec::new(); n];
    let mut reference_frames = Vec::new();
    let mut previous_v: Vec<Option<Vec<f32>>> = vec![None; n];
    let mut previous_reference: Option<(Vec<f32>, Vec<bool>)> = None;
    // One renderer per method for the whole sequence, moved from frame to frame.
    let mut kept: Vec<Option<Detached>> = runs.iter().map(|_| None).collect();
    let mut reference_label = String::new();
    let bar = progress::bar(u64::from(job.frames), "sequence frames");
    for i in 0..job.frames {
        let scene_t = job.animation.frame(scene, i, job.frames);
        let (g, reference) = truth::for_scene(ctx, &scene_t, job.reference, &job.cache)?;
        reference_label = truth::mode_label(&reference.mode);
        let mask: Vec<bool> = (0..g.position.len()).map(|p| g.is_geometry(p)).collect();
        let shaded_reference = run_files::shaded_image(&reference.values, &g, &scene_t);
        let mut line = format!(
            "frame {}/{}: reference {}",
            i + 1,
            job.frames,
            if reference.cached { "cached" } else { "traced" }
        );
        // `--reuse both`: each method's V without reuse, for its reuse run to equal.
        let mut without: Vec<Option<Vec<f32>>> = vec![None; job.methods.len()];
        for (k, (mi, reuse, label)) in runs.iter().enumerate() {
            let method = &job.methods[*mi];
            let attach = std::time::Instant::now();
            let mut renderer = match kept[k].take() {
                Some(d) => d.attach(ctx, &scene_t)?,
                None => Renderer::with_reuse(ctx, &scene_t, method, *reuse)?,
            };
            let attach_ms = attach.elapsed().as_secs_f64() * 1e3;
            let f = renderer.frame(FrameOptions {
                mode: job.timing,
                pictures: false,
            })?;
            let mut stages_ms = std::collections::BTreeMap::new();
            if job.timing == TimingMode::Stages {
                stages_ms = f.stages_ms.clone();
                stages_ms.insert("attach".to_string(), attach_ms);
            }
            let detached = renderer.detach();
            let kept_bytes = detached.maps_kept().bytes();
            kept[k] = Some(detached);
            let differ = (0..mask.len())
                .filter(|&p| f.gbuffer.is_geometry(p) != mask[p])
                .count();
            if differ > 0 {
                return Err(Error::gpu(format!(
                    "{} frame {i}: the G-buffer differs from the reference's in {differ} pixels",
                    method.label()
                )));
            }
            let shaded = run_files::shaded_image(&f.visibility, &f.gbuffer, &scene_t);
            let m = metrics::compute(
                &f.visibility,
                &reference.values,
                &mask,
                &shaded,
                &shaded_reference,
                w,
                h,
            )?;
            let abs = abs_error_image(&f.visibility, &reference.values, &mask, w, h, ERROR_SCALE)?;
            let pair = match (&previous_v[k], &previous_reference) {
                (Some(v0), Some((r0, mask0))) => Some(temporal::frame_pair(
                    v0,
                    &f.visibility,
                    r0,
                    &reference.values,
                    mask0,
                    &mask,
                )),
                _ => None,
            };
            line += &format!(
                ", {label} {} maps ({} rendered) RMSE {:.4}",
                f.output.shadow_maps, f.reuse.rendered, m.rmse
            );
            // A full cache says so: the maps it pushed out are rendered again when needed.
            if f.reuse.evicted > 0 {
                line += &format!(" ({} evicted: the map budget is full)", f.reuse.evicted);
            }
            if let Some(p) = &pair {
                line += &format!(" pop {}", p.popping_pixels);
            }
            let equal = match (*reuse, &without[*mi]) {
                (true, Some(v0)) => Some(
                    bytemuck::cast_slice::<f32, u32>(v0)
                        == bytemuck::cast_slice::<f32, u32>(&f.visibility),
                ),
                _ => None,
            };
            if equal == Some(false) {
                line += " V DIFFERS from the frame without reuse";
            }
            rows.push(FrameRow {
                core: RowCore {
                    maps: f.output.shadow_maps,
                    map_size: scene_t.render.shadow_map_size,
                    rmse: m.rmse,
                    frame_ms: f.total_ms,
                    adapter: adapter.clone(),
                    ..RowCore::of(&scene.name, &method.label(), method)
                },
                label: label.clone(),
                frame: i,
                metrics: m,
                temporal: pair,
                light_center: scene_t.light.center.to_array(),
                camera_eye: scene_t.camera.eye.to_array(),
                reuse: *reuse,
                reuse_counts: f.reuse,
                v_equal_without_reuse: equal,
                kept_bytes,
                stages_ms,
            });
            method_frames[k].push(apng::side_by_side(&[&shaded, &abs]));
            if !*reuse && job.reuse == Reuse::Both {
                without[*mi] = Some(f.visibility.clone());
            }
            previous_v[k] = Some(f.visibility);
        }
        reference_frames.push(shaded_reference);
        previous_reference = Some((reference.values, mask));
        progress::suspend(|| log(&line));
        bar.inc(1);
    }
    bar.finish_and_clear();

    let labels: Vec<String> = runs.iter().map(|(_, _, l)| l.clone()).collect();
    let mut summaries: Vec<MethodSummary> = runs
        .iter()
        .map(|(m, _, l)| summarise(l, job.methods[*m].name(), &rows))
        .collect();
    if job.reuse == Reuse::Both {
        time_ratios(&mut summaries, &rows);
    }
    let charts = charts_of(&rows, &labels)?;
    let mut animations = vec![(
        "reference (shaded)".to_string(),
        apng::encode(&reference_frames, FRAME_DELAY_MS)?,
    )];
    for (label, frames) in labels.iter().zip(&method_frames) {
        animations.push((
            format!("{label}: shaded | |error of V|"),
            apng::encode(frames, FRAME_DELAY_MS)?,
        ));
    }
    let description = job.animation.describe(scene);
    let adapter = format!("{} ({})", ctx.summary.name, ctx.summary.backend);
    let mut outcome = SequenceOutcome {
        scene: scene.name.clone(),
        title: format!(
            "Temporal sequence: {}, {description}, {} frames at {w}x{h}",
            scene.name, job.frames
        ),
        description,
        resolution: [w, h],
        reference: reference_label,
        adapter,
        rows,
        summaries,
        charts,
        animations,
        files: Vec::new(),
    };
    outcome.files = files_of(&outcome, job)?;
    Ok(outcome)
}

/// `--reuse both`: each reuse run's frame time over its method's run without, frame by frame
/// after the first, and the median of those ratios (the runs come in pairs, without then with).
pub fn time_ratios(summaries: &mut [MethodSummary], rows: &[FrameRow]) {
    for pair in summaries.chunks_mut(2) {
        if let [off, on] = pair {
            if off.reuse || !on.reuse {
                continue;
            }
            let ms = |label: &str, frame: u32| {
                rows.iter()
                    .find(|r| r.label == label && r.frame == frame)
                    .map(|r| r.core.frame_ms)
            };
            let ratios: Vec<f64> = rows
                .iter()
                .filter(|r| r.label == on.label && r.frame > 0)
                .filter_map(|r| {
                    ms(&off.label, r.frame)
                        .filter(|&o| o > 0.0)
                        .map(|o| r.core.frame_ms / o)
                })
                .collect();
            on.time_ratio_to_without_reuse = (!ratios.is_empty()).then(|| median(&ratios));
        }
    }
}

/// The figures of one method over all frames of `rows`.
pub fn summarise(label: &str, method: &str, rows: &[FrameRow]) -> MethodSummary {
    let mine: Vec<&FrameRow> = rows.iter().filter(|r| r.label == label).collect();
    let count = mine.len().max(1) as f64;
    let pairs: Vec<FramePair> = mine.iter().filter_map(|r| r.temporal).collect();
    let times: Vec<f64> = mine.iter().map(|r| r.core.frame_ms).collect();
    let worst = mine
        .iter()
        .filter_map(|r| r.temporal.map(|t| (r.frame, t.popping_pixels)))
        .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)));
    let later: Vec<&&FrameRow> = mine.iter().filter(|r| r.frame > 0).collect();
    let mean_later = |f: &dyn Fn(&FrameRow) -> f64| {
        if later.is_empty() {
            0.0
        } else {
            later.iter().map(|r| f(r)).sum::<f64>() / later.len() as f64
        }
    };
    let (texels, used) = later.iter().fold((0u64, 0u64), |(a, b), r| {
        (a + r.reuse_counts.texels, b + r.reuse_counts.texels_used)
    });
    let compared: Vec<bool> = mine
        .iter()
        .filter_map(|r| r.v_equal_without_reuse)
        .collect();
    MethodSummary {
        label: label.to_string(),
        method: method.to_string(),
        frames: mine.len() as u32,
        mean_rmse: mine.iter().map(|r| r.metrics.rmse).sum::<f64>() / count,
        mean_bad_pixel_share: mine.iter().map(|r| r.metrics.bad_pixel_share).sum::<f64>() / count,
        temporal: temporal::sequence(&pairs),
        maps_mean: mine.iter().map(|r| f64::from(r.core.maps)).sum::<f64>() / count,
        maps_min: mine.iter().map(|r| r.core.maps).min().unwrap_or(0),
        maps_max: mine.iter().map(|r| r.core.maps).max().unwrap_or(0),
        median_ms: if times.is_empty() {
            0.0
        } else {
            median(&times)
        },
        worst_pop_frame: worst,
        reuse: mine.first().is_some_and(|r| r.reuse),
        mean_ms_after_first: mean_later(&|r| r.core.frame_ms),
        median_ms_after_first: if later.is_empty() {
            0.0
        } else {
            median(&later.iter().map(|r| r.core.frame_ms).collect::<Vec<_>>())
        },
        rendered_mean_after_first: mean_later(&|r| f64::from(r.reuse_counts.rendered)),
        kept_mean_after_first: mean_later(&|r| f64::from(r.reuse_counts.kept)),
        texel_share_after_first: if used == 0 {
            0.0
        } else {
            texels as f64 / used as f64
        },
        v_equal_frames: (!compared.is_empty()).then(|| {
            (
                compared.iter().filter(|&&e| e).count() as u32,
                compared.len() as u32,
            )
        }),
        time_ratio_to_without_reuse: None,
        kept_bytes_max: mine.iter().map(|r| r.kept_bytes).max().unwrap_or(0),
    }
}

fn series(
    rows: &[FrameRow],
    labels: &[String],
    keep: impl Fn(&FrameRow) -> bool,
    y: impl Fn(&FrameRow) -> Option<f64>,
) -> Vec<FrameSeries> {
    labels
        .iter()
        .map(|l| FrameSeries {
            name: l.clone(),
            points: rows
                .iter()
                .filter(|r| &r.label == l && keep(r))
                .filter_map(|r| y(r).map(|v| (f64::from(r.frame), v)))
                .collect(),
        })
        .filter(|s| !s.points.is_empty())
        .collect()
}

/// The per-frame charts: error, temporal error, popping, and the adaptive methods' map counts.
fn charts_of(rows: &[FrameRow], labels: &[String]) -> Result<Vec<(String, String, String)>> {
    let all = |_: &FrameRow| true;
    let mut out = vec![
        (
            "error_per_frame".to_string(),
            "RMSE of V per frame, each frame against its own reference".to_string(),
            charts::per_frame_svg("Error per frame", "RMSE of V", &series(rows, labels, all, |r| Some(r.metrics.rmse)))?,
        ),
        (
            "popping_per_frame".to_string(),
            "Popping per frame: share of pixels whose V changes by more than 1/32 while the reference changes by less than 1/256".to_string(),
            charts::per_frame_svg(
                "Popping per frame",
                "popping pixels (% of geometry)",
                &series(rows, labels, all, |r| r.temporal.map(|t| 100.0 * t.popping_share)),
            )?,
        ),
        (
            "temporal_error_per_frame".to_string(),
            "Temporal error per frame: RMSE of (V_t − V_t−1) − (R_t − R_t−1)".to_string(),
            charts::per_frame_svg(
                "Temporal error per frame",
                "RMSE of the change of V against the reference's",
                &series(rows, labels, all, |r| r.temporal.map(|t| t.temporal_rmse)),
            )?,
        ),
    ];
    out.push((
        "frame_time_per_frame".to_string(),
        "Frame time per frame: wall clock of one frame-mode frame (the first frame keeps nothing)"
            .to_string(),
        charts::per_frame_svg(
            "Frame time per frame",
            "frame time (ms)",
            &series(rows, labels, all, |r| Some(r.core.frame_ms)),
        )?,
    ));
    out.push((
        "maps_rendered_per_frame".to_string(),
        "Shadow maps rasterized whole per frame (the rest were kept, or partly drawn again where a mesh moved; docs/reuse.md)".to_string(),
        charts::per_frame_svg("Shadow maps rendered per frame", "maps rendered", &series(rows, labels, all, |r| Some(f64::from(r.reuse_counts.rendered))))?,
    ));
    let adaptive = series(
        rows,
        labels,
        |r| r.core.method == "adaptive",
        |r| Some(f64::from(r.core.maps)),
    );
    if !adaptive.is_empty() {
        out.push((
            "maps_per_frame".to_string(),
            "Shadow maps per frame of the adaptive methods".to_string(),
            charts::per_frame_svg(
                "Shadow maps per frame (adaptive)",
                "shadow maps rendered",
                &adaptive,
            )?,
        ));
    }
    Ok(out)
}

fn json<T: Serialize + ?Sized>(v: &T, what: &str) -> Result<String> {
    serde_json::to_string(v).map_err(|e| Error::io_text(what.into(), e.to_string()))
}

/// frames.jsonl/.csv, summary.json/.csv, charts (SVG and PNG), animations.
fn files_of(o: &SequenceOutcome, job: &SequenceJob) -> Result<Vec<(String, Vec<u8>)>> {
    let mut files = Vec::new();
    let mut jsonl = String::new();
    for r in &o.rows {
        jsonl += &json(r, "frames.jsonl")?;
        jsonl.push('\n');
    }
    files.push(("frames.jsonl".to_string(), jsonl.into_bytes()));
    files.push((
        "frames.csv".to_string(),
        tables::frames_csv(&o.rows).into_bytes(),
    ));
    let summary = serde_json::json!({
        "scene": job.scene.name,
        "scene_origin": job.scene.origin,
        "animation": job.animation,
        "description": o.description,
        "frames": job.frames,
        "resolution": o.resolution,
        "reference": o.reference,
        "adapter": o.adapter,
        "clock": "wall clock per frame (submit to device poll wait), frame mode, one frame per method and frame, ms",
        "definitions": "docs/sequence.md",
        "version": run_files::version(),
        "methods": o.summaries,
        "reuse": job.reuse,
    });
    let pretty = serde_json::to_vec_pretty(&summary)
        .map_err(|e| Error::io_text("summary.json".into(), e.to_string()))?;
    files.push(("summary.json".to_string(), pretty));
    files.push((
        "summary.csv".to_string(),
        tables::summary_csv(&o.summaries).into_bytes(),
    ));
    for (stem, _, svg) in &o.charts {
        files.push((format!("charts/{stem}.png"), svg_to_png(svg, 1.0)?));
        files.push((format!("charts/{stem}.svg"), svg.clone().into_bytes()));
    }
    let slugs = crate::report::unique_slugs(
        std::iter::once("reference").chain(o.summaries.iter().map(|s| s.label.as_str())),
    );
    for ((_, bytes), slug) in o.animations.iter().zip(&slugs) {
        files.push((format!("animations/{slug}.png"), bytes.clone()));
    }
    Ok(files)
}

/// Writes every file, then `report.html`; returns its path.
pub fn write(out: &std::path::Path, o: &SequenceOutcome) -> Result<std::path::PathBuf> {
    let mut files = o.files.clone();
    let title = format!("Penumbra: temporal sequence on {}", o.scene);
    files.push((
        "report.html".to_string(),
        crate::report::page::page(&title, &[section::section(o)?])?.into_bytes(),
    ));
    run_files::write_files(out, &files)?;
    Ok(out.join("report.html"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::kept_maps::ReuseCounts;

    fn row(
        label: &str,
        frame: u32,
        reuse: bool,
        ms: f64,
        rendered: u32,
        kept: u32,
        equal: Option<bool>,
    ) -> FrameRow {
        FrameRow {
            core: RowCore {
                scene: "s".into(),
                method: "regular".into(),
                maps: rendered + kept,
                frame_ms: ms,
                ..Default::default()
            },
            label: label.into(),
            frame,
            metrics: Metrics::default(),
            temporal: None,
            light_center: [0.0; 3],
            camera_eye: [0.0; 3],
            reuse,
            reuse_counts: ReuseCounts {
                rendered,
                kept,
                redrawn: 0,
                texels: rendered as u64 * 4,
                texels_used: (rendered + kept) as u64 * 4,
                evicted: 0,
            },
            v_equal_without_reuse: equal,
            kept_bytes: if reuse { 1024 } else { 0 },
            stages_ms: Default::default(),
        }
    }

    #[test]
    fn reuse_figures_after_the_first_frame_and_the_ratio_to_the_run_without() {
        let rows = [
            row("a (reuse off)", 0, false, 100.0, 8, 0, None),
            row("a (reuse on)", 0, true, 110.0, 8, 0, Some(true)),
            row("a (reuse off)", 1, false, 90.0, 8, 0, None),
            row("a (reuse on)", 1, true, 30.0, 0, 8, Some(true)),
            row("a (reuse off)", 2, false, 110.0, 8, 0, None),
            row("a (reuse on)", 2, true, 22.0, 2, 6, Some(false)),
            // A load spike on the frame without reuse: the paired ratio's median shrugs it off.
            row("a (reuse off)", 3, false, 900.0, 8, 0, None),
            row("a (reuse on)", 3, true, 36.0, 0, 8, Some(true)),
        ];
        let mut s = vec![
            summarise("a (reuse off)", "regular", &rows),
            summarise("a (reuse on)", "regular", &rows),
        ];
        time_ratios(&mut s, &rows);
        let (off, on) = (&s[0], &s[1]);
        assert_eq!((off.reuse, on.reuse), (false, true));
        assert_eq!(
            (off.mean_ms_after_first, on.mean_ms_after_first),
            (1100.0 / 3.0, 88.0 / 3.0)
        );
        assert_eq!(
            (off.median_ms_after_first, on.median_ms_after_first),
            (110.0, 30.0)
        );
        // Ratios 30/90, 22/110, 36/900: their median is 0.2.
        assert_eq!(on.time_ratio_to_without_reuse, Some(0.2));
        assert_eq!(off.time_ratio_to_without_reuse, None);
        assert_eq!(
            (on.rendered_mean_after_first, on.kept_mean_after_first),
            (2.0 / 3.0, 22.0 / 3.0)
        );
        assert_eq!(on.texel_share_after_first, 8.0 / 96.0);
        assert_eq!(on.v_equal_frames, Some((3, 4)));
        assert_eq!(off.v_equal_frames, None);
        assert_eq!(on.kept_bytes_max, 1024);
    }

    #[test]
    fn both_runs_each_method_without_then_with_reuse() {
        assert_eq!(
            Reuse::Both.runs("x"),
            vec![
                (false, "x (reuse off)".to_string()),
                (true, "x (reuse on)".to_string())
            ]
        );
        assert_eq!(Reuse::On.runs("x"), vec![(true, "x".to_string())]);
        assert_eq!(
            Reuse::parse("sometimes").unwrap_err().to_string(),
            "--reuse sometimes: use on, off or both"
        );
    }
}
