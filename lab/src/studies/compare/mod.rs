//! `compare` and `sweep`: every method run on one scene, timed (`measure`), judged against the
//! CPU reference over geometry pixels (`metrics`), and written as `results.jsonl`, `results.csv`,
//! pictures, charts and the report. Everything is encoded in memory before the first file is
//! written, so bad input or a failed run leaves no partial output.

pub mod command;
pub mod methods_list;
pub mod plan;
pub mod regions;
pub mod run_args;
pub mod sweep;
pub mod sweep_command;
pub mod table;

use crate::frame::FrameOptions;
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::metrics::{abs_error_image, signed_error_image};
use crate::record::judge::Judge;
use crate::record::measure::{self, Phase};
use crate::record::run_files;
use crate::record::{self, Provenance, RunInfo};
use crate::reference::truth::{self, Cache, ReferenceImage};
use crate::reference::ReferenceMode;
use crate::report::charts::ResultRow;
use crate::report::results::{write_from_rows, LoadedRow};
use crate::scene::Scene;
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What `penumbra` with no arguments compares (docs/method.md: the seed's method, the project's
/// recommended preset, and the regular grids they are measured against; docs/methods.md: one of
/// each single-map family, hard, PCF, PCSS and a moment map).
pub const DEFAULT_METHODS: &str = "hard,pcf:kernel=poisson,pcss,msm,regular:n=5,layout=centred,regular:n=17,adaptive:preset=seed,adaptive:preset=balanced";

/// The main job's methods (`penumbra` with no command): the defaults, then what the tool
/// recommends at one RMSE target: the frame-wide budget and the per-region method, side by side.
pub const MAIN_JOB_METHODS: &str = "hard,pcf:kernel=poisson,pcss,msm,regular:n=5,layout=centred,regular:n=17,adaptive:preset=seed,adaptive:preset=balanced,auto:target=0.02,regions:target=0.02";

/// |error| where the error maps saturate: one scale for every method, so colours compare.
pub const ERROR_SCALE: f32 = 0.25;

pub use record::CLOCK;

pub struct CompareJob<'a> {
    pub scene: &'a Scene,
    pub methods: Vec<Method>,
    pub repeats: u32,
    pub reference: ReferenceMode,
    pub cache: Cache,
    /// One per method: where its row comes from (scene digests, spec and shard).
    pub provenance: Vec<Provenance>,
    /// After its timing, one untimed frame per method with its decision pictures on, on the
    /// method's own renderer ([`CompareOutcome::pictures`]).
    pub pictures: bool,
    /// `--certify K`: each method's last frame gets a certified bound (docs/certify.md).
    pub certify: Option<crate::certify::Options>,
}

pub struct CompareOutcome {
    pub rows: Vec<ResultRow>,
    pub reference: ReferenceImage,
    /// Which pixels hold geometry (the metrics' mask).
    pub geometry: Vec<bool>,
    /// Every output file but the report: (path relative to the output folder, bytes).
    pub files: Vec<(String, Vec<u8>)>,
    /// Per method, the decision pictures of its pictures frame (empty unless the job asked).
    pub pictures: Vec<Vec<(String, image::RgbImage)>>,
}

fn json_bytes(v: &impl serde::Serialize, what: &str) -> Result<Vec<u8>> {
    serde_json::to_vec_pretty(v).map_err(|e| Error::io_text(what.into(), e.to_string()))
}

/// The reference files every compare output holds (shared by merged sweeps).
pub const REFERENCE_FILES: [&str; 4] = [
    "reference.exr",
    "reference.png",
    "reference_shaded.png",
    "reference.json",
];

/// Runs the job; `log` gets one line per finished step (reference, each method).
pub fn run(ctx: &GpuContext, job: &CompareJob, log: &dyn Fn(&str)) -> Result<CompareOutcome> {
    let scene = job.scene;
    if job.provenance.len() != job.methods.len() {
        return Err(Error::param(format!(
            "compare: {} methods but {} provenance records",
            job.methods.len(),
            job.provenance.len()
        )));
    }
    let (w, h) = (scene.render.width, scene.render.height);
    let (g, reference) = truth::for_scene(ctx, scene, job.reference, &job.cache)?;
    let judge = Judge::new(scene, &g, reference.values.clone());
    let geometry = judge.geometry_pixels();
    log(&reference_line(&reference, geometry));
    if let Some(o) = &job.certify {
        if o.pixels > geometry {
            return Err(Error::param(format!(
                "--certify {}: more than the frame's {geometry} geometry pixels",
                o.pixels
            )));
        }
    }
    // One certifier for every method: the scene's truth tracer and second opinion, built once.
    let mut certifier = job
        .certify
        .map(|o| {
            crate::frame::certify::FrameCertifier::new(
                ctx,
                scene,
                o,
                crate::frame::certify::ProxyKind::SecondOpinion,
            )
        })
        .transpose()?;
    let mut files = vec![
        (
            "reference.exr".to_string(),
            run_files::visibility_exr(&reference.values, w, h)?,
        ),
        (
            "reference.png".to_string(),
            run_files::visibility_png(&reference.values, w, h)?,
        ),
        (
            "reference_shaded.png".to_string(),
            run_files::png(&judge.shaded_reference)?,
        ),
        (
            "reference.json".to_string(),
            json_bytes(&reference.record(scene, geometry), "reference.json")?,
        ),
    ];
    let labels: Vec<String> = job.methods.iter().map(Method::label).collect();
    let slugs = crate::report::unique_slugs(labels.iter().map(String::as_str));
    let bar = crate::progress::bar(
        measure::frame_count(job.methods.len(), job.repeats),
        "frames",
    );
    // Each method's last frame is judged and pictured as it arrives, then dropped.
    type Judged = (
        crate::metrics::Metrics,
        BTreeMap<String, String>,
        Vec<(String, Vec<u8>)>,
        serde_json::Value,
        Option<record::Certified>,
    );
    let mut judge_frame = |i: usize, f: &crate::frame::FrameResult| -> Result<Judged> {
        let method = &job.methods[i];
        let judged = judge.judge(scene, &method.label(), f)?;
        let abs = abs_error_image(
            &f.visibility,
            &judge.reference,
            &judge.mask,
            w,
            h,
            ERROR_SCALE,
        )?;
        let signed = signed_error_image(
            &f.visibility,
            &judge.reference,
            &judge.mask,
            w,
            h,
            ERROR_SCALE,
        )?;
        let dir = format!("images/{}", slugs[i]);
        let mut images = BTreeMap::new();
        let mut own = Vec::new();
        for (key, bytes) in [
            ("shaded", run_files::png(&judged.shaded)?),
            (
                "visibility",
                run_files::visibility_png(&f.visibility, w, h)?,
            ),
            ("abs_error", run_files::png(&abs)?),
            ("signed_error", run_files::png(&signed)?),
        ] {
            let path = format!("{dir}/{key}.png");
            images.insert(key.to_string(), path.clone());
            own.push((path, bytes));
        }
        images.insert("reference".into(), "reference_shaded.png".into());
        // The float image too, as `render` writes it, so every method's V can be read back exactly.
        own.push((
            format!("{dir}/visibility.exr"),
            run_files::visibility_exr(&f.visibility, w, h)?,
        ));
        // run.json waits for the measurement's timing (below): this frame only knows its waits.
        let mut record =
            run_files::run_record(scene, method, f, &ctx.summary, ctx.timestamps_trusted);
        // The certificate of the judged frame, outside its timing.
        let certified = match certifier.as_mut() {
            Some(c) => {
                let r = c.certify(f)?;
                record["certify"] = serde_json::to_value(&r)
                    .map_err(|e| Error::io_text("run.json".into(), e.to_string()))?;
                Some(record::Certified::of(&r))
            }
            None => None,
        };
        Ok((judged.metrics, images, own, record, certified))
    };
    let mut on_frame = |m: &Method, phase: Phase, _: &crate::frame::FrameResult| {
        bar.set_message(format!("{} {phase}", m.label()));
        bar.inc(1);
    };
    // The pictures frame runs in the method's measure window, on its own renderer, after the timing.
    let mut pictures = Vec::new();
    let mut after = |_: usize, r: &mut crate::frame::Renderer| -> Result<()> {
        if job.pictures {
            pictures.push(
                r.frame(FrameOptions {
                    mode: TimingMode::Frame,
                    pictures: true,
                })?
                .output
                .pictures,
            );
        }
        Ok(())
    };
    let measured = measure::measure_with(
        ctx,
        scene,
        &job.methods,
        job.repeats,
        &mut on_frame,
        &mut judge_frame,
        &mut after,
    )?;
    bar.finish_and_clear();
    let info = RunInfo {
        scene: &scene.name,
        resolution: [w, h],
        shadow_map_size: scene.render.shadow_map_size,
        adapter: &ctx.summary,
        reference: truth::mode_label(&reference.mode),
        repeats: job.repeats,
    };
    let mut rows = Vec::new();
    for (((method, m), provenance), slug) in job
        .methods
        .iter()
        .zip(measured)
        .zip(&job.provenance)
        .zip(&slugs)
    {
        // A setting that failed is a row that says why; the others go on.
        let m = match m {
            Ok(m) => m,
            Err(reason) => {
                log(&record::failed_line(&method.label(), &reason));
                rows.push(record::failed_row(
                    &info,
                    method,
                    &reason,
                    provenance.clone(),
                ));
                continue;
            }
        };
        let (metrics, images, own, record, certified) = m.judged;
        files.extend(own);
        let record = run_files::measured_record(record, &m.timing);
        files.push((
            format!("images/{slug}/run.json"),
            json_bytes(&record, "run.json")?,
        ));
        let mut row = record::row(
            &info,
            method,
            &m.timing,
            metrics,
            images,
            provenance.clone(),
        );
        row.certify = certified;
        log(&format!(
            "{}: {} shadow maps, median {:.1} ms (min {:.1}, max {:.1}), RMSE {:.4}",
            row.label,
            row.core.maps,
            row.core.frame_ms,
            row.frame_ms_min,
            row.frame_ms_max,
            row.metrics.rmse
        ));
        rows.push(row);
    }
    if let Some(line) =
        record::failed_summary(rows.iter().filter(|r| !r.measured()).count(), rows.len())
    {
        log(&line);
    }
    files.extend(record::result_files(&rows)?);
    let geometry = judge.mask.clone();
    Ok(CompareOutcome {
        rows,
        reference,
        geometry,
        files,
        pictures,
    })
}

/// The reference's one-line summary (also printed by `penumbra reference`).
pub fn reference_line(r: &ReferenceImage, geometry: usize) -> String {
    let mut what = format!(
        "reference {} at {}x{} ({geometry} geometry pixels)",
        truth::mode_label(&r.mode),
        r.width,
        r.height
    );
    if let Some((mean, max)) = r.std_error {
        what += &format!(", Monte Carlo standard error of V mean {mean:.4}, max {max:.4}");
    }
    match (&r.trace, &r.cache_file) {
        (Some(t), _) if t.tracer == "gpu" => format!(
            "{what}: traced on the GPU in {:.1} s, {:.1} M rays/s ({:.1} M samples/s){}",
            t.seconds,
            t.rays_per_s / 1e6,
            t.samples_per_s / 1e6,
            t.ties.filter(|&n| n > 0).map_or(String::new(), |n| format!(
                ", {n} rays decided by a tie in f32"
            ))
        ),
        (Some(t), _) => format!(
            "{what}: traced in {:.1} s, {:.1} M rays/s ({:.1} M samples/s) on {} threads",
            t.seconds,
            t.rays_per_s / 1e6,
            t.samples_per_s / 1e6,
            t.threads
        ),
        (None, Some(p)) => format!("{what}: from the cache {}", p.display()),
        (None, None) => what,
    }
}

/// Writes every file and the report from the rows as one set (crate::record::output_set): `out` ends up
/// holding the new set, or on any failure or interrupt the old one. Returns the path of `report.html`.
pub fn write(out: &Path, outcome: &CompareOutcome) -> Result<PathBuf> {
    write_set(out, &outcome.files, &outcome.rows)
}

/// Files plus the report of `rows`, as one set (compare, sweep, merge).
pub fn write_set(out: &Path, files: &[(String, Vec<u8>)], rows: &[ResultRow]) -> Result<PathBuf> {
    let set = crate::record::output_set::OutputSet::begin(out)?;
    for (name, bytes) in files {
        set.write(name, bytes)?;
    }
    let rows: Vec<LoadedRow> = rows
        .iter()
        .map(|r| LoadedRow {
            row: r.clone(),
            base: set.path().to_path_buf(),
        })
        .collect();
    {
        let _writing = set.writing();
        write_from_rows(&rows, set.path())?;
    }
    set.commit()?;
    Ok(out.join("report.html"))
}
