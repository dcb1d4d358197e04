//! `penumbra environment`: every environment method on the panorama scenes, judged against the
//! importance-sampled reference (compare), with the environment charts (error against time and
//! against samples, one series per method), each method's panorama picture (chosen lights or
//! quadtree cells) and error maps, and the closing table with the env-adaptive verdict.

pub(crate) mod charts;
pub mod command;

use self::charts::{env_chart_svg, EnvAxis};
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::record::Provenance;
use crate::reference::truth;
use crate::report::charts::{svg_to_png, ResultRow};
use crate::report::page::data_uri;
use crate::scene::Scene;
use crate::studies::compare::{self, CompareJob};
use crate::{Error, Result};
use std::path::{Path, PathBuf};

pub const DEFAULT_SCENES: &str = "env-bunny,env-dragon";
pub const DEFAULT_METHODS: &str = "env-pixels:res=16x8,env-pixels:res=32x16,env-pixels:res=64x32,env-pixels:res=32x16;at=vertex,\
env-shadowmaps:k=4,env-shadowmaps:k=16,env-shadowmaps:k=64,env-shadowmaps:k=256,ssao,env-pixels:res=32x16;ssao=on,\
env-adaptive:max_level=2;min_share=0.02,env-adaptive:max_level=3;min_share=0.02,env-adaptive";

/// What `penumbra environment` runs: the lists as given, checked by [`run`] before any frame.
#[derive(Debug, Clone)]
pub struct EnvironmentJob {
    /// Scenes with an [environment], comma-separated.
    pub scenes: String,
    /// Methods, comma-separated as in compare (a method's own parameters joined by `;`).
    pub methods: String,
    /// Timed frames per method (median reported).
    pub repeats: u32,
    /// M: the reference takes M×M importance samples per pixel.
    pub samples: u32,
    /// `key=value` render overrides as given (the rows' provenance records them).
    pub set: Vec<String>,
    /// Trace the references without the cache: nothing is read from it or stored in it.
    pub no_cache: bool,
}

/// One scene's outcome: rows and the pictures of the panorama.
pub struct SceneOutcome {
    pub scene: String,
    pub rows: Vec<ResultRow>,
    pub reference_error: Option<(f32, f32)>,
    pub pictures: Vec<(String, Vec<u8>)>,
}

/// Methods from the flag: `,` between methods, `;` between one method's parameters.
pub fn parse_methods(list: &str) -> Result<Vec<Method>> {
    let methods: Vec<Method> = list
        .split(',')
        .filter(|s| !s.trim().is_empty())
        .map(|s| Method::parse(&s.trim().replace(';', ","), &[]))
        .collect::<penumbra::Result<_>>()?;
    if methods.is_empty() {
        return Err(Error::param("--methods: no method given".into()));
    }
    Ok(methods)
}

/// A run's files by name, as `run_files::write_files` takes them.
pub type NamedFiles = Vec<(String, Vec<u8>)>;

pub fn run(
    ctx: &GpuContext,
    job: &EnvironmentJob,
    overrides: &[(String, String)],
    log: &dyn Fn(&str),
) -> Result<(Vec<SceneOutcome>, NamedFiles)> {
    let methods = parse_methods(&job.methods)?;
    let mode = truth::parse_mode("continuous", job.samples)?;
    if job.repeats == 0 || job.repeats > 100 {
        return Err(Error::param(format!(
            "--repeats must be in 1..=100, got {}",
            job.repeats
        )));
    }
    // Every scene loads (and has an environment) before anything runs.
    let mut scenes = Vec::new();
    for name in job
        .scenes
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
    {
        let scene = Scene::load(name, overrides)?;
        if scene.environment.is_none() {
            return Err(Error::param(format!(
                "--scenes: `{name}` has no [environment] (docs/environment.md)"
            )));
        }
        scenes.push(scene);
    }
    if scenes.is_empty() {
        return Err(Error::param("--scenes: no scene given".into()));
    }
    let cache = truth::Cache::default_for(job.no_cache);
    let mut outcomes = Vec::new();
    let mut files = Vec::new();
    for scene in &scenes {
        let provenance =
            vec![Provenance::of_scene("environment", scene, &job.set, None); methods.len()];
        let compare_job = CompareJob {
            scene,
            methods: methods.clone(),
            repeats: job.repeats,
            reference: mode,
            cache: cache.clone(),
            provenance,
            pictures: true,
            certify: None,
        };
        let outcome = compare::run(ctx, &compare_job, log)?;
        let prefix = format!("{}/", crate::report::unique_slugs([scene.name.as_str()])[0]);
        for (name, bytes) in outcome.files {
            files.push((format!("{prefix}{name}"), bytes));
        }
        let mut rows = outcome.rows;
        for r in &mut rows {
            for path in r.images.values_mut() {
                *path = format!("{prefix}{path}");
            }
        }
        // The decision pictures: compare's untimed pictures frame, per method that draws any.
        let mut pictures = Vec::new();
        for (m, drawn) in methods.iter().zip(&outcome.pictures) {
            for (name, img) in drawn {
                let path = format!(
                    "{prefix}pictures/{}/{name}",
                    crate::report::unique_slugs([m.label().as_str()])[0]
                );
                let bytes = crate::record::run_files::png(img)?;
                files.push((path.clone(), bytes.clone()));
                pictures.push((format!("{}: {}", scene.name, m.label()), bytes));
            }
        }
        outcomes.push(SceneOutcome {
            scene: scene.name.clone(),
            rows,
            reference_error: outcome.reference.std_error,
            pictures,
        });
    }
    let all: Vec<ResultRow> = outcomes.iter().flat_map(|o| o.rows.clone()).collect();
    for (axis, stem) in [
        (EnvAxis::Time, "env_error_vs_time"),
        (EnvAxis::Samples, "env_error_vs_samples"),
    ] {
        let svg = env_chart_svg(&all, axis)?;
        files.push((format!("charts/{stem}.png"), svg_to_png(&svg, 1.0)?));
        files.push((format!("charts/{stem}.svg"), svg.into_bytes()));
    }
    files.push((
        "environment.md".into(),
        closing_table(&outcomes).into_bytes(),
    ));
    // Every scene's rows in one results.jsonl/.csv at the top (each scene's own are in its folder).
    files.extend(crate::record::result_files(&all)?);
    Ok((outcomes, files))
}

/// The best (lowest-RMSE) row of `method` whose RMSE is at most `target`, by samples then time.
fn reaching<'a>(rows: &'a [ResultRow], method: &str, target: f64) -> Option<&'a ResultRow> {
    rows.iter()
        .filter(|r| r.core.method == method && r.metrics.rmse <= target)
        .min_by(|a, b| {
            a.core
                .maps
                .cmp(&b.core.maps)
                .then(a.core.frame_ms.total_cmp(&b.core.frame_ms))
        })
}

/// Per scene: every row (samples, time, RMSE), then whether env-adaptive reaches each
/// env-shadowmaps row's error with fewer samples or less time.
pub fn closing_table(outcomes: &[SceneOutcome]) -> String {
    let mut s = String::new();
    for o in outcomes {
        s += &format!("### {}\n\n", o.scene);
        if let Some((mean, max)) = o.reference_error {
            s += &format!("Reference standard error of V: mean {mean:.4}, max {max:.4} over geometry pixels.\n\n");
        }
        s += "| method | samples | median ms | RMSE | FLIP mean |\n|---|---:|---:|---:|---:|\n";
        for r in &o.rows {
            s += &format!(
                "| `{}` | {} | {:.1} | {:.4} | {:.4} |\n",
                r.label(),
                r.core.maps,
                r.core.frame_ms,
                r.metrics.rmse,
                r.metrics.flip_mean
            );
        }
        s += "\n";
        for base in o.rows.iter().filter(|r| r.core.method == "env-shadowmaps") {
            let line = match reaching(&o.rows, "env-adaptive", base.metrics.rmse) {
                Some(a) => format!(
                    "- `{}` (RMSE {:.4}, {} maps, {:.1} ms): `{}` reaches RMSE {:.4} with {} samples ({}) in {:.1} ms ({}).\n",
                    base.label(), base.metrics.rmse, base.core.maps, base.core.frame_ms, a.label(), a.metrics.rmse, a.core.maps,
                    if a.core.maps < base.core.maps { "fewer" } else { "not fewer" }, a.core.frame_ms,
                    if a.core.frame_ms < base.core.frame_ms { "less time" } else { "more time" }
                ),
                None => format!("- `{}` (RMSE {:.4}): no env-adaptive row reaches its error.\n", base.label(), base.metrics.rmse),
            };
            s += &line;
        }
        s += "\n";
    }
    s
}

/// The environment section appended to report.html: charts, panorama pictures, the table.
pub fn section(outcomes: &[SceneOutcome], files: &[(String, Vec<u8>)]) -> String {
    let esc = |t: &str| {
        t.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
    };
    let mut h = String::from("<section id=\"environment\"><h2>Environment lighting (seed 002)</h2>\n<p>V is the unoccluded fraction of the panorama's radiance-weighted cosine integral (docs/environment.md). Samples: pixel lights (env-pixels), median-cut maps (env-shadowmaps) or quadtree leaves (env-adaptive); every time is wall clock.</p>\n");
    for (name, bytes) in files
        .iter()
        .filter(|(n, _)| n.starts_with("charts/env_") && n.ends_with(".svg"))
    {
        h += &format!(
            "<figure>{}<figcaption>{}</figcaption></figure>\n",
            String::from_utf8_lossy(bytes),
            esc(name)
        );
    }
    for o in outcomes {
        h += &format!(
            "<h3>{} panorama: the lights and cells each method chose</h3>\n<div class=\"gallery\">",
            esc(&o.scene)
        );
        for (caption, png) in &o.pictures {
            h += &format!("<figure><img src=\"{}\" width=\"512\" alt=\"{}\"><figcaption>{}</figcaption></figure>", data_uri("image/png", png), esc(caption), esc(caption));
        }
        h += "</div>\n";
    }
    h += &format!(
        "<h3>Closing table</h3><pre>{}</pre></section>\n",
        esc(&closing_table(outcomes))
    );
    h
}

/// Writes the set (report.html from compare's report of every row) and appends the section.
pub fn write(
    out: &Path,
    outcomes: &[SceneOutcome],
    files: &[(String, Vec<u8>)],
) -> Result<PathBuf> {
    let rows: Vec<ResultRow> = outcomes.iter().flat_map(|o| o.rows.clone()).collect();
    let html = compare::write_set(out, files, &rows)?;
    crate::report::page::append_to_page(&html, &[section(outcomes, files)])?;
    Ok(html)
}
