//! `compare` and `sweep`: every method run on one scene, timed (`measure`), judged against the
//! CPU reference over geometry pixels (`metrics`), and written as `results.jsonl`, `results.csv`,
//! pictures, charts and the report. Everything is encoded in memory before the first file is
//! written, so bad input or a failed run leaves no partial output.

pub mod csv;
pub mod measure;
pub mod methods_list;
pub mod sweep;
pub mod table;

use crate::charts::{svg_to_png, ResultRow};
use crate::ground_truth::{self, Cache, ReferenceImage};
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::metrics::{self, abs_error_image, signed_error_image};
use crate::reference::ReferenceMode;
use crate::report::results::{self as report_results, LoadedRow};
use crate::scene::Scene;
use crate::{output, Error, Result};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// |error| where the error maps saturate: one scale for every method, so colours compare.
pub const ERROR_SCALE: f32 = 0.25;

/// How `total_ms` and `stages_ms` were taken (stored in every row).
pub const CLOCK: &str = "wall clock (submit to device poll wait), ms; total_ms: frame mode (only the method's own waits); \
stages_ms: one stages-mode run (a wait after every stage)";

pub struct CompareJob<'a> {
    pub scene: &'a Scene,
    pub methods: Vec<Method>,
    pub repeats: u32,
    pub reference: ReferenceMode,
    pub cache: Cache,
}

pub struct CompareOutcome {
    pub rows: Vec<ResultRow>,
    pub reference: ReferenceImage,
    /// Which pixels hold geometry (the metrics' mask).
    pub geometry: Vec<bool>,
    /// Every output file but the report: (path relative to the output folder, bytes).
    pub files: Vec<(String, Vec<u8>)>,
}

fn json_bytes(v: &impl serde::Serialize, what: &str) -> Result<Vec<u8>> {
    serde_json::to_vec_pretty(v).map_err(|e| Error::Io { path: what.into(), message: e.to_string() })
}

/// Runs the job; `log` gets one line per finished step (reference, each method).
pub fn run(ctx: &GpuContext, job: &CompareJob, log: &dyn Fn(&str)) -> Result<CompareOutcome> {
    let scene = job.scene;
    let (w, h) = (scene.render.width, scene.render.height);
    let (g, reference) = ground_truth::for_scene(ctx, scene, job.reference, &job.cache)?;
    let mask: Vec<bool> = (0..g.position.len()).map(|i| g.is_geometry(i)).collect();
    let geometry = mask.iter().filter(|m| **m).count();
    log(&reference_line(&reference, geometry));
    let shaded_reference = output::shaded_image(&reference.values, &g, scene);
    let mut files = vec![
        ("reference.exr".to_string(), output::visibility_exr(&reference.values, w, h)?),
        ("reference.png".to_string(), output::visibility_png(&reference.values, w, h)?),
        ("reference_shaded.png".to_string(), output::png(&shaded_reference)?),
        ("reference.json".to_string(), json_bytes(&reference.record(scene, geometry), "reference.json")?),
    ];
    let labels: Vec<String> = job.methods.iter().map(Method::label).collect();
    let slugs = crate::report::unique_slugs(labels.iter().map(String::as_str));
    let mut rows = Vec::new();
    for (method, slug) in job.methods.iter().zip(&slugs) {
        let m = measure::measure(ctx, scene, method, job.repeats)?;
        let f = &m.frame;
        let differ = (0..mask.len()).filter(|&i| f.gbuffer.is_geometry(i) != mask[i]).count();
        if differ > 0 {
            return Err(Error::Gpu(format!("{}: the G-buffer differs from the reference's in {differ} pixels", method.label())));
        }
        let shaded = output::shaded_image(&f.visibility, &f.gbuffer, scene);
        let metrics = metrics::compute(&f.visibility, &reference.values, &mask, &shaded, &shaded_reference, w, h)?;
        let abs = abs_error_image(&f.visibility, &reference.values, &mask, w, h, ERROR_SCALE)?;
        let signed = signed_error_image(&f.visibility, &reference.values, &mask, w, h, ERROR_SCALE)?;
        let dir = format!("images/{slug}");
        let mut images = BTreeMap::new();
        for (key, bytes) in [
            ("shaded", output::png(&shaded)?),
            ("visibility", output::visibility_png(&f.visibility, w, h)?),
            ("abs_error", output::png(&abs)?),
            ("signed_error", output::png(&signed)?),
        ] {
            let path = format!("{dir}/{key}.png");
            images.insert(key.to_string(), path.clone());
            files.push((path, bytes));
        }
        images.insert("reference".into(), "reference_shaded.png".into());
        // The float image too, as `render` writes it, so every method's V can be read back exactly.
        files.push((format!("{dir}/visibility.exr"), output::visibility_exr(&f.visibility, w, h)?));
        let record = output::run_record(scene, method, f, &ctx.summary, ctx.timestamps_trusted);
        files.push((format!("{dir}/run.json"), json_bytes(&record, "run.json")?));
        let row = ResultRow {
            scene: scene.name.clone(),
            method: method.name().to_string(),
            params: method.params_json(),
            adapter: serde_json::to_value(&ctx.summary).unwrap_or_default(),
            shadow_maps: f.output.shadow_maps,
            total_ms: m.median_ms,
            total_ms_min: m.min_ms,
            total_ms_max: m.max_ms,
            stages_ms: m.stages_ms.clone(),
            metrics,
            label: method.label(),
            syncs: f.output.syncs,
            total_ms_runs: m.totals_ms.clone(),
            setup_ms: m.setup_ms,
            resolution: Some([w, h]),
            shadow_map_size: Some(scene.render.shadow_map_size),
            reference: ground_truth::mode_label(&reference.mode),
            repeats: job.repeats,
            clock: CLOCK.into(),
            version: output::version(),
            images,
        };
        log(&format!(
            "{}: {} shadow maps, median {:.1} ms (min {:.1}, max {:.1}), RMSE {:.4}",
            row.label, row.shadow_maps, row.total_ms, row.total_ms_min, row.total_ms_max, row.metrics.rmse
        ));
        rows.push(row);
    }
    let mut jsonl = String::new();
    for r in &rows {
        jsonl += &serde_json::to_string(r).map_err(|e| Error::Io { path: "results.jsonl".into(), message: e.to_string() })?;
        jsonl.push('\n');
    }
    files.push(("results.jsonl".into(), jsonl.into_bytes()));
    files.push(("results.csv".into(), csv::render(&rows).into_bytes()));
    for (stem, _, svg) in report_results::charts(&rows)? {
        files.push((format!("charts/{stem}.png"), svg_to_png(&svg, 1.0)?));
        files.push((format!("charts/{stem}.svg"), svg.into_bytes()));
    }
    Ok(CompareOutcome { rows, reference, geometry: mask, files })
}

/// The reference's one-line summary (also printed by `penumbra reference`).
pub fn reference_line(r: &ReferenceImage, geometry: usize) -> String {
    let what = format!("reference {} at {}x{} ({geometry} geometry pixels)", ground_truth::mode_label(&r.mode), r.width, r.height);
    match (&r.trace, &r.cache_file) {
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

/// Writes every file (creating sub-folders, each file through a temporary name), then the
/// report from the rows just written. Returns the path of `report.html`.
pub fn write(out: &Path, outcome: &CompareOutcome) -> Result<PathBuf> {
    for (name, bytes) in &outcome.files {
        let path = out.join(name);
        let dir = path.parent().unwrap_or(out);
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let file = path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
        let tmp = dir.join(format!(".{file}.tmp"));
        std::fs::write(&tmp, bytes).map_err(|e| Error::io(&tmp, e))?;
        std::fs::rename(&tmp, &path).map_err(|e| Error::io(&path, e))?;
    }
    let rows: Vec<LoadedRow> = outcome.rows.iter().map(|r| LoadedRow { row: r.clone(), base: out.to_path_buf() }).collect();
    report_results::write_from_rows(&rows, out)
}
