//! The hybrid-map study (`penumbra hybrid`, docs/hybrid.md): plain and hybrid shadow maps of one
//! scene measured side by side in one run.
//! - Hard shadows against the exact hard shadow from the light's centre (`reference --mode point`):
//!   mismatched pixels and bytes per map for every map configuration, and the time of the raster,
//!   the merge (`hybrid_build`) and the lookup (`shade`). The hard configurations are interleaved
//!   round by round, so all see the same machine load.
//! - Multi-map methods (regular:n=17, adaptive) with hybrid maps against plain maps of a fixed size
//!   and of the hybrid maps' measured memory, against the continuous reference.

pub(crate) mod charts;
pub mod command;
pub mod files;

use crate::frame::{FrameOptions, FrameResult, Renderer};
use crate::gpu::kernels;
use crate::gpu::stages::{outside_frame, Stage};
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::metrics::Metrics;
use crate::record::judge::Judge;
use crate::record::measure::median;
use crate::record::RowCore;
use crate::reference::truth::{self, Cache};
use crate::reference::ReferenceMode;
use crate::scene::{MapKind, Scene};
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One map representation of the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Maps {
    Plain(u32),
    Hybrid { base: u32, levels: u32 },
}

impl Maps {
    pub fn label(&self) -> String {
        match *self {
            Maps::Plain(size) => format!("plain {size}"),
            Maps::Hybrid { base, levels } => format!("hybrid {base}→{}", base >> levels),
        }
    }

    /// The scene with this representation (`eps` for hybrid maps).
    pub fn apply(&self, scene: &Scene, eps: f32) -> Scene {
        let mut s = scene.clone();
        match *self {
            Maps::Plain(size) => {
                s.render.maps = MapKind::Plain;
                s.render.shadow_map_size = size;
            }
            Maps::Hybrid { base, levels } => {
                s.render.maps = MapKind::Hybrid;
                s.render.hybrid = crate::scene::HybridDef { base, levels, eps };
                s.render.shadow_map_size = base;
            }
        }
        s
    }
}

/// `512` or `2048/2` (base / levels).
pub fn parse_maps(text: &str, hybrid: bool) -> Result<Maps> {
    let bad = |why: &str| Error::param(format!("map configuration `{text}`: {why}"));
    let number = |v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|_| bad("not a whole number"))
    };
    if !hybrid {
        let size = number(text)?;
        return if (8..=16384).contains(&size) {
            Ok(Maps::Plain(size))
        } else {
            Err(bad("size must be in 8..=16384"))
        };
    }
    let (base, levels) = text
        .split_once('/')
        .ok_or_else(|| bad("give BASE/LEVELS, e.g. 2048/2"))?;
    let (base, levels) = (number(base)?, number(levels)?);
    if !(1..=2).contains(&levels) {
        return Err(bad("levels must be 1 or 2"));
    }
    if !(8..=16384).contains(&base) || base % (1 << levels) != 0 {
        return Err(bad("base must be in 8..=16384 and a multiple of 2^levels"));
    }
    Ok(Maps::Hybrid { base, levels })
}

pub struct HybridJob {
    pub scene: Scene,
    /// Hard-shadow configurations.
    pub hard: Vec<Maps>,
    pub eps: f32,
    pub repeats: u32,
    /// Multi-map methods, each with `multi_hybrid` against `multi_plain` sizes and the plain size of
    /// equal memory.
    pub multi: Vec<Method>,
    pub multi_hybrid: Maps,
    pub multi_plain: Vec<u32>,
    pub multi_repeats: u32,
    pub cache: Cache,
}

/// One method with one map representation.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct HybridRow {
    /// Scene, the label as spec, method, params, maps, map size (the raster's side, the base of
    /// a hybrid map), RMSE, median frame time, adapter (by name), build.
    #[serde(flatten)]
    pub core: RowCore,
    /// `hard` (point reference) or `multi` (continuous reference).
    pub part: String,
    /// The method's label (`regular:n=5`).
    pub label: String,
    /// The map representation (`plain 512`, `hybrid 2048→512`).
    pub map_config: String,
    pub kind: String,
    pub levels: u32,
    pub bytes_per_map: f64,
    /// `bytes_per_map` over a plain map of the raster's size.
    pub share_of_plain: f64,
    pub reference: String,
    pub mismatch_share: f64,
    pub metrics: Metrics,
    pub syncs: u32,
    /// Frame wall clock: min and max over the timed frames (the median is `frame_ms`).
    pub frame_ms_min: f64,
    pub frame_ms_max: f64,
    /// From the stages-mode frame: `shadow_raster`, `hybrid_build` and the lookup stages.
    pub raster_ms: f64,
    pub build_ms: f64,
    pub lookup_ms: f64,
    pub stages_ms: BTreeMap<String, f64>,
    /// Hybrid only: the method record's `hybrid` entry (store, transient raster, flushes).
    pub store: serde_json::Value,
    pub resolution: u32,
    pub clock: String,
}

pub struct HybridOutcome {
    pub rows: Vec<HybridRow>,
    pub files: Vec<(String, Vec<u8>)>,
}

struct Measured {
    totals: Vec<f64>,
    stages: BTreeMap<String, f64>,
    last: FrameResult,
}

/// Warm-up (optional), one stages-mode frame, then `repeats` frame-mode rounds over all `scenes`.
fn measure(
    ctx: &GpuContext,
    scenes: &[Scene],
    method: &Method,
    warmup: bool,
    repeats: u32,
    log: &dyn Fn(&str),
) -> Result<Vec<Measured>> {
    let options = |mode| FrameOptions {
        mode,
        pictures: false,
    };
    let mut renderers = scenes
        .iter()
        .map(|s| Renderer::new(ctx, s, method))
        .collect::<penumbra::Result<Vec<_>>>()?;
    let bar = crate::progress::bar(
        scenes.len() as u64 * (1 + warmup as u64 + repeats as u64),
        "frames",
    );
    if warmup {
        for r in &mut renderers {
            r.frame(options(TimingMode::Frame))?;
            bar.inc(1);
        }
    }
    let mut out = Vec::new();
    for r in &mut renderers {
        let f = r.frame(options(TimingMode::Stages))?;
        bar.inc(1);
        out.push(Measured {
            totals: Vec::new(),
            stages: f.stages_ms.clone(),
            last: f,
        });
    }
    for _ in 0..repeats {
        for (r, m) in renderers.iter_mut().zip(&mut out) {
            let f = r.frame(options(TimingMode::Frame))?;
            bar.inc(1);
            m.totals.push(f.total_ms);
            m.last = f;
        }
    }
    bar.finish_and_clear();
    log(&format!(
        "  {}: {} configuration(s) measured",
        method.label(),
        scenes.len()
    ));
    Ok(out)
}

#[allow(clippy::too_many_arguments)]
fn row(
    ctx: &GpuContext,
    part: &str,
    scene: &Scene,
    method: &Method,
    maps: Maps,
    m: &Measured,
    judge: &Judge,
    reference: &str,
) -> Result<HybridRow> {
    let f = &m.last;
    let judged = judge.judge(scene, &method.label(), f)?;
    let size = scene.render.shadow_map_size;
    let plain = size as f64 * size as f64 * 4.0;
    let store = f
        .output
        .record
        .get("hybrid")
        .cloned()
        .unwrap_or(serde_json::Value::Null);
    let (kind, levels, bytes) = match maps {
        Maps::Plain(_) => ("plain", 0, plain),
        Maps::Hybrid { levels, .. } => (
            "hybrid",
            levels,
            store["bytes_per_map"].as_f64().unwrap_or(0.0),
        ),
    };
    let stage = |k: &str| m.stages.get(k).copied().unwrap_or(0.0);
    let totals = if m.totals.is_empty() {
        vec![f.total_ms]
    } else {
        m.totals.clone()
    };
    Ok(HybridRow {
        core: RowCore {
            maps: f.output.shadow_maps,
            map_size: size,
            rmse: judged.metrics.rmse,
            frame_ms: median(&totals),
            adapter: ctx.summary.name.clone().into(),
            ..RowCore::of(&scene.name, &method.label(), method)
        },
        part: part.into(),
        label: method.label(),
        map_config: maps.label(),
        kind: kind.into(),
        levels,
        bytes_per_map: bytes,
        share_of_plain: bytes / plain,
        reference: reference.into(),
        mismatch_share: judged.metrics.mismatch_share,
        metrics: judged.metrics,
        syncs: f.output.syncs,
        frame_ms_min: totals.iter().copied().fold(f64::INFINITY, f64::min),
        frame_ms_max: totals.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        // Whichever raster drew the maps (`raster = auto` may pick either); the other reads 0.
        raster_ms: stage(Stage::SHADOW_RASTER.name) + stage(Stage::RASTER_COMPUTE.name),
        build_ms: stage(Stage::HYBRID_BUILD.name),
        // The lookup: the stages whose kernels read the maps (shade, shadow_test, pcf, pcss).
        lookup_ms: kernels::all()
            .filter(|(_, k)| k.reads_maps)
            .map(|(s, _)| stage(s.name))
            .sum(),
        stages_ms: m
            .stages
            .iter()
            .filter(|(k, _)| !outside_frame(k))
            .map(|(k, v)| (k.clone(), *v))
            .collect(),
        store,
        resolution: scene.render.width,
        clock: "wall clock (submit to wait)".into(),
    })
}

/// The plain map size with the memory of `bytes` per map (a multiple of 8 texels per side).
pub fn equal_memory_size(bytes: f64) -> u32 {
    (((bytes / 4.0).sqrt() / 8.0).round() as u32).max(1) * 8
}

pub fn run(ctx: &GpuContext, job: &HybridJob, log: &dyn Fn(&str)) -> Result<HybridOutcome> {
    let mut rows = Vec::new();
    let hard = Method::hard();
    if !job.hard.is_empty() {
        let mode = ReferenceMode::Point { s: 0.5, t: 0.5 };
        let (g, reference) = truth::for_scene(ctx, &job.scene, mode, &job.cache)?;
        let judge = Judge::new(&job.scene, &g, reference.values.clone());
        let label = truth::mode_label(&mode);
        log(&format!(
            "hard shadows against the {label} reference ({} geometry pixels):",
            judge.geometry_pixels()
        ));
        let scenes: Vec<Scene> = job
            .hard
            .iter()
            .map(|m| m.apply(&job.scene, job.eps))
            .collect();
        let measured = measure(ctx, &scenes, &hard, true, job.repeats, log)?;
        for ((maps, scene), m) in job.hard.iter().zip(&scenes).zip(&measured) {
            let r = row(ctx, "hard", scene, &hard, *maps, m, &judge, &label)?;
            log(&format!(
                "  {}: {:.3} MiB per map, {:.3}% mismatched, median {:.1} ms (raster {:.1}, build {:.1}, lookup {:.1})",
                r.map_config,
                r.bytes_per_map / 1048576.0,
                100.0 * r.mismatch_share,
                r.core.frame_ms,
                r.raster_ms,
                r.build_ms,
                r.lookup_ms
            ));
            rows.push(r);
        }
    }
    if !job.multi.is_empty() {
        let mode = ReferenceMode::DEFAULT_CONTINUOUS;
        let (g, reference) = truth::for_scene(ctx, &job.scene, mode, &job.cache)?;
        let judge = Judge::new(&job.scene, &g, reference.values.clone());
        let label = truth::mode_label(&mode);
        for method in &job.multi {
            log(&format!(
                "{} against the {label} reference:",
                method.label()
            ));
            let hybrid_scene = job.multi_hybrid.apply(&job.scene, job.eps);
            let m = measure(
                ctx,
                std::slice::from_ref(&hybrid_scene),
                method,
                false,
                job.multi_repeats,
                log,
            )?;
            let h = row(
                ctx,
                "multi",
                &hybrid_scene,
                method,
                job.multi_hybrid,
                &m[0],
                &judge,
                &label,
            )?;
            let mut sizes = job.multi_plain.clone();
            sizes.push(equal_memory_size(h.bytes_per_map));
            sizes.sort_unstable();
            sizes.dedup();
            log(&format!(
                "  {}: {:.3} MiB per map (plain {} has the same), RMSE {:.5}, median {:.0} ms",
                h.map_config,
                h.bytes_per_map / 1048576.0,
                equal_memory_size(h.bytes_per_map),
                h.core.rmse,
                h.core.frame_ms
            ));
            rows.push(h);
            for size in sizes {
                let maps = Maps::Plain(size);
                let scene = maps.apply(&job.scene, job.eps);
                let m = measure(
                    ctx,
                    std::slice::from_ref(&scene),
                    method,
                    false,
                    job.multi_repeats,
                    log,
                )?;
                let r = row(ctx, "multi", &scene, method, maps, &m[0], &judge, &label)?;
                log(&format!(
                    "  {}: RMSE {:.5}, median {:.0} ms",
                    r.map_config, r.core.rmse, r.core.frame_ms
                ));
                rows.push(r);
            }
        }
    }
    let files = files::files(&rows)?;
    Ok(HybridOutcome { rows, files })
}
