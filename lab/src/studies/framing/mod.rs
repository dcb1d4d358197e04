//! The framing study (docs/studies.md): when does adaptive sampling pay? The same scenes at several
//! screen resolutions and light sizes, so the penumbra's width on screen varies; every method is
//! run through `compare` at each configuration, and maps and error are charted against the width.

pub(crate) mod charts;
pub mod command;
pub(crate) mod width;

use self::charts::{framing_svg, WidthAxis, WidthPoint};
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::record::row_core::RowCore;
use crate::reference::truth::Cache;
use crate::reference::ReferenceMode;
use crate::report::charts::{svg_to_png, ResultRow};
use crate::scene::Scene;
use crate::studies::compare::{self, CompareJob};
use crate::{Error, Result};
use serde::Serialize;

pub struct FramingJob {
    /// Scenes as loaded (their own resolution and light are the 1x configuration).
    pub scenes: Vec<Scene>,
    pub resolutions: Vec<u32>,
    /// Factors on the light's edge vectors (the penumbra's width scales with the light).
    pub light_scales: Vec<f32>,
    pub methods: Vec<Method>,
    pub repeats: u32,
    pub reference: ReferenceMode,
    pub cache: Cache,
}

/// One method at one configuration: the compare row plus where it was taken.
#[derive(Serialize)]
pub struct FramingRow {
    /// The compare row's core (scene, spec, method, params, maps, map size, RMSE, frame time,
    /// adapter, build), at the top level as in every study's row.
    #[serde(flatten)]
    pub core: RowCore,
    pub resolution: u32,
    pub light_scale: f32,
    /// Median penumbra width in pixels of the reference (`width`), and the pixels it was taken over.
    pub penumbra_width_px: Option<f64>,
    pub penumbra_pixels: usize,
    pub label: String,
    /// Folder (relative to the study's output) with this configuration's compare output.
    pub config: String,
    pub row: ResultRow,
}

pub struct FramingOutcome {
    pub rows: Vec<FramingRow>,
    pub files: Vec<(String, Vec<u8>)>,
}

fn io_error(what: &str, e: impl std::fmt::Display) -> Error {
    Error::io_text(what.into(), e.to_string())
}

/// The scene at one configuration: square screen of `resolution`, the light `scale` times the size.
/// The rectangle is `Scene::light`; another kind scales its emitter, which the reference traces,
/// and its stand-in square follows (scaling the stand-in alone moved the methods' light points
/// and left the reference's emitter as it was).
pub fn configure(scene: &Scene, resolution: u32, scale: f32) -> Scene {
    let mut s = scene.clone();
    s.render.width = resolution;
    s.render.height = resolution;
    let emitter = s.emitter.scaled(scale);
    match emitter.stand_in(&s.bounds) {
        Some(stand_in) => {
            s.emitter = emitter;
            s.light = stand_in;
        }
        None => {
            s.light.edge_u *= scale;
            s.light.edge_v *= scale;
        }
    }
    s
}

pub fn run(ctx: &GpuContext, job: &FramingJob, log: &dyn Fn(&str)) -> Result<FramingOutcome> {
    let mut rows = Vec::new();
    let mut files = Vec::new();
    for base in &job.scenes {
        for &resolution in &job.resolutions {
            for &scale in &job.light_scales {
                let scene = configure(base, resolution, scale);
                let config = format!("configs/{}-{resolution}px-light{scale}", base.name);
                log(&format!("{config}:"));
                let overrides = vec![
                    format!("resolution={resolution}"),
                    format!("light_scale={scale}"),
                ];
                let provenance = crate::record::Provenance {
                    overrides,
                    ..crate::record::Provenance::of_scene("framing", &scene, &[], None)
                };
                let provenance = vec![provenance; job.methods.len()];
                let cj = CompareJob {
                    scene: &scene,
                    methods: job.methods.clone(),
                    repeats: job.repeats,
                    reference: job.reference,
                    cache: job.cache.clone(),
                    provenance,
                    pictures: false,
                    certify: None,
                };
                let outcome = compare::run(ctx, &cj, log)?;
                let r = &outcome.reference;
                let width =
                    width::penumbra_width_px(&r.values, &outcome.geometry, r.width, r.height);
                log(&format!(
                    "  penumbra width: {}",
                    width.map_or("none".into(), |(w, n)| format!("{w:.1} px over {n} px"))
                ));
                for row in outcome.rows {
                    rows.push(FramingRow {
                        core: row.core.clone(),
                        resolution,
                        light_scale: scale,
                        penumbra_width_px: width.map(|w| w.0),
                        penumbra_pixels: width.map_or(0, |w| w.1),
                        label: row.label(),
                        config: config.clone(),
                        row,
                    });
                }
                files.extend(
                    outcome
                        .files
                        .into_iter()
                        .map(|(name, bytes)| (format!("{config}/{name}"), bytes)),
                );
            }
        }
    }
    let points: Vec<WidthPoint> = rows
        .iter()
        .filter_map(|r| {
            let series = if job.scenes.len() > 1 {
                format!("{}: {}", r.core.scene, r.label)
            } else {
                r.label.clone()
            };
            r.penumbra_width_px.map(|w| WidthPoint {
                series,
                width_px: w,
                maps: r.core.maps as f64,
                rmse: r.core.rmse,
            })
        })
        .collect();
    for (stem, axis) in [
        ("framing_maps", WidthAxis::Maps),
        ("framing_rmse", WidthAxis::Rmse),
    ] {
        let svg = framing_svg(&points, axis).map_err(|e| io_error(stem, e))?;
        files.push((
            format!("charts/{stem}.png"),
            svg_to_png(&svg, 1.0).map_err(|e| io_error(stem, e))?,
        ));
        files.push((format!("charts/{stem}.svg"), svg.into_bytes()));
    }
    let mut jsonl = String::new();
    for r in &rows {
        jsonl += &serde_json::to_string(r).map_err(|e| io_error("framing.jsonl", e))?;
        jsonl.push('\n');
    }
    files.push(("framing.jsonl".into(), jsonl.into_bytes()));
    files.push(("framing.csv".into(), csv(&rows).into_bytes()));
    files.push(("framing.md".into(), markdown(&rows).into_bytes()));
    Ok(FramingOutcome { rows, files })
}

fn csv(rows: &[FramingRow]) -> String {
    let own = ["resolution", "light_scale", "penumbra_width_px", "label"];
    let header = RowCore::csv_header(&own);
    let cells = rows.iter().map(|r| {
        let mut c = r.core.cells();
        c.extend([
            r.resolution.to_string(),
            r.light_scale.to_string(),
            r.penumbra_width_px
                .map_or(String::new(), |w| format!("{w:.2}")),
            r.label.clone(),
        ]);
        c
    });
    crate::record::csv::lines(std::iter::once(header).chain(cells))
}

/// One table per scene: a row per configuration, maps and RMSE per method.
pub fn markdown(rows: &[FramingRow]) -> String {
    let mut s = String::from("# Framing study\n\nMaps used and RMSE of V (continuous reference) against the penumbra's median width on screen.\n");
    let mut scenes: Vec<&str> = rows.iter().map(|r| r.core.scene.as_str()).collect();
    scenes.dedup();
    let mut methods: Vec<&str> = rows.iter().map(|r| r.label.as_str()).collect();
    methods.sort();
    methods.dedup();
    for scene in scenes {
        s += &format!("\n## {scene}\n\n| resolution | light | penumbra width (px) |");
        for m in &methods {
            s += &format!(" {m} maps / RMSE |");
        }
        s += "\n|---:|---:|---:|";
        s += &"---:|".repeat(methods.len());
        s += "\n";
        let mut configs: Vec<&str> = rows
            .iter()
            .filter(|r| r.core.scene == scene)
            .map(|r| r.config.as_str())
            .collect();
        configs.dedup();
        for c in configs {
            let of: Vec<&FramingRow> = rows.iter().filter(|r| r.config == c).collect();
            let first = of[0];
            s += &format!(
                "| {}² | {}x | {} |",
                first.resolution,
                first.light_scale,
                first
                    .penumbra_width_px
                    .map_or("–".into(), |w| format!("{w:.1}"))
            );
            for m in &methods {
                match of.iter().find(|r| r.label == *m) {
                    Some(r) => s += &format!(" {} / {:.4} |", r.core.maps, r.core.rmse),
                    None => s += " – |",
                }
            }
            s += "\n";
        }
    }
    s
}
