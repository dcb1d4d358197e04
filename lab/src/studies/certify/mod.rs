//! `penumbra certify`: how often the certified bound covers the measured RMSE, and how sharp it
//! is (docs/certify.md §4). For each scene and method one frame; for each proxy, K and draw, the
//! pixels the design draws, their exact truth, and the bounds on the frame's RMSE against the RMSE
//! measured over every geometry pixel. The exact truth at the drawn pixels is read from the full
//! reference, which equals the GPU tracer's at every pixel (lab/tests/truth_trace.rs): the study
//! measures the statistics, `render --certify` the cost.
//!
//! The calibrated bound's stretch is fitted here ([`fit_stretch`]) on the fitting half of the
//! shipped scenes (`calibration::SPLIT`) and read on the checking half and the held-out scenes.

pub mod command;
pub mod promise;

use crate::certify::bound::{self, BoundKind};
use crate::certify::design::Design;
use crate::certify::{certificate, design, Sampled};
use crate::frame::certify::{proxy, Opinion, ProxyKind, SECOND_OPINION};
use crate::frame::{FrameOptions, Renderer};
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::record::row_core::read_csv;
use crate::record::RowCore;
use crate::reference::truth::{self, Cache};
use crate::reference::ReferenceMode;
use crate::scene::Scene;
use crate::studies::calibration::{half, Half};
use crate::{Error, Result};
use serde::{Deserialize, Serialize};

/// K, the pixels drawn, by default.
pub const DEFAULT_PIXELS: [usize; 3] = [1024, 2048, 4096];
/// Draws per (scene, method, proxy, K).
pub const DEFAULT_DRAWS: u32 = 5;
/// The K the stretch is fitted at, and the share of the fitting half's draws it must cover.
pub const FIT_PIXELS: usize = 2048;
pub const FIT_COVERAGE: f64 = 0.95;
/// The proxies compared.
pub const PROXIES: [ProxyKind; 2] = [ProxyKind::Band, ProxyKind::SecondOpinion];

/// One draw: its bounds against the measured RMSE.
///
/// Its serde reads the study's own columns of `certify.csv`; [`parse_csv`] reads the core from
/// the core's columns (see [`crate::record::row_core::read_csv`]).
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct Row {
    /// Scene, the method (its label as the spec), its maps and map size, the RMSE measured over
    /// every geometry pixel (`rmse`), the frame's wall clock, adapter and build.
    #[serde(skip)]
    pub core: RowCore,
    pub half: String,
    pub proxy: String,
    pub pixels: usize,
    pub draw: u32,
    pub unique_pixels: usize,
    pub sampled_rmse: f64,
    /// Student t at 1 − δ (no stretch), the distribution-free per-frame bound.
    pub t_bound: f64,
    pub per_frame_bound: f64,
    pub delta: f64,
    pub resolution: u32,
}

impl Row {
    /// The study's own columns, after the core's.
    pub const OWN: [&'static str; 11] = [
        "half",
        "proxy",
        "pixels",
        "draw",
        "unique_pixels",
        "sampled_rmse",
        "t_bound",
        "per_frame_bound",
        "delta",
        "resolution",
        "calibrated_bound",
    ];

    fn cells(&self) -> Vec<String> {
        let mut c = self.core.cells();
        c.extend([
            self.half.clone(),
            self.proxy.clone(),
            self.pixels.to_string(),
            self.draw.to_string(),
            self.unique_pixels.to_string(),
            self.sampled_rmse.to_string(),
            self.t_bound.to_string(),
            self.per_frame_bound.to_string(),
            self.delta.to_string(),
            self.resolution.to_string(),
            (bound::STRETCH * self.t_bound).to_string(),
        ]);
        c
    }

    /// The bound of `kind` with the t bound stretched by `stretch`.
    pub fn bound(&self, kind: BoundKind, stretch: f64) -> f64 {
        match kind {
            BoundKind::PerFrame => self.per_frame_bound,
            BoundKind::Calibrated => stretch * self.t_bound,
        }
    }
}

/// The rows as CSV (with the calibrated bound at the engine's stretch as the last column).
pub fn csv(rows: &[Row]) -> String {
    crate::record::csv::lines(
        std::iter::once(RowCore::csv_header(&Row::OWN)).chain(rows.iter().map(Row::cells)),
    )
}

/// Rows from the CSV [`csv`] writes (the committed results' reader). Files written before the
/// core (results/certify-coverage) name the method by its label in `method`, have no `spec`,
/// and call the RMSE `measured_rmse`: the label becomes the spec, its name the method.
pub fn parse_csv(text: &str) -> Result<Vec<Row>> {
    let rows =
        read_csv::<Row>(text, &[]).map_err(|e| Error::param(format!("certify rows: {e}")))?;
    Ok(rows
        .into_iter()
        .map(|(mut core, row)| {
            if core.spec.is_empty() {
                core.spec = core.method.clone();
                core.method = core.spec.split(':').next().unwrap_or_default().into();
            }
            Row { core, ..row }
        })
        .collect())
}

/// The seed of draw `d` at K pixels: the same pixels for every method with the same proxy values.
fn seed(draw: u32, pixels: usize) -> u64 {
    0x5eed_0055 ^ ((draw as u64) << 32) ^ pixels as u64
}

/// What the study asks of each scene.
pub struct Job<'a> {
    pub methods: &'a [String],
    pub pixels: &'a [usize],
    pub draws: u32,
    pub delta: f64,
    pub mode: ReferenceMode,
}

/// Every method on one scene: the rows of its draws, and the methods the light refused.
pub fn run_scene(
    ctx: &GpuContext,
    name: &str,
    sets: &[(String, String)],
    job: &Job,
    cache: &Cache,
    log: &dyn Fn(&str),
) -> Result<Vec<Row>> {
    let scene = Scene::load(name, sets)?;
    let (g, reference) = truth::for_scene(ctx, &scene, job.mode, cache)?;
    let subset: Vec<bool> = (0..g.position.len()).map(|i| g.is_geometry(i)).collect();
    let geometry = subset.iter().filter(|s| **s).count();
    let second = {
        let f = Renderer::new(ctx, &scene, &Method::parse(SECOND_OPINION, &[])?)?.frame(
            FrameOptions {
                mode: TimingMode::Frame,
                pictures: false,
            },
        )?;
        let bound = f
            .output
            .bound
            .ok_or_else(|| Error::limit(format!("{SECOND_OPINION}: no bound")))?;
        Opinion {
            visibility: f.visibility,
            bound,
        }
    };
    for &k in job.pixels.iter().filter(|&&k| k > geometry) {
        log(&format!(
            "{}: K = {k} skipped: more than its {geometry} geometry pixels",
            scene.name
        ));
    }
    let adapter =
        serde_json::Value::from(format!("{} ({})", ctx.summary.name, ctx.summary.backend));
    let mut rows = Vec::new();
    for spec in job.methods {
        let method = Method::parse(spec, &[])?;
        if let Err(e) = method.check_light(&scene) {
            log(&format!("{}: {} skipped ({e})", scene.name, method.label()));
            continue;
        }
        let f = Renderer::new(ctx, &scene, &method)?.frame(FrameOptions {
            mode: TimingMode::Frame,
            pictures: false,
        })?;
        let measured = rmse(&f.visibility, &reference.values, &subset);
        let core = RowCore {
            maps: f.output.shadow_maps,
            map_size: scene.render.shadow_map_size,
            rmse: measured,
            frame_ms: f.total_ms,
            adapter: adapter.clone(),
            ..RowCore::of(&scene.name, &method.label(), &method)
        };
        for kind in PROXIES {
            let q = proxy(
                kind,
                &f.visibility,
                &subset,
                g.width,
                g.height,
                Some(&second),
            );
            let design = Design::new(&subset, &q, design::DEFENSIVE)?;
            for &k in job.pixels {
                if k > geometry {
                    // K ≤ N, as `--certify` asks: a scene of fewer geometry pixels skips that K.
                    continue;
                }
                for d in 0..job.draws {
                    let sampled =
                        Sampled::from_values(design.draw(k, seed(d, k)), &reference.values);
                    let c = certificate(
                        &f.visibility,
                        &sampled,
                        &design,
                        job.delta,
                        BoundKind::Calibrated,
                    );
                    rows.push(Row {
                        core: core.clone(),
                        half: half(&scene.name).name().to_string(),
                        proxy: kind.name().to_string(),
                        pixels: k,
                        draw: d,
                        unique_pixels: c.unique_pixels,
                        sampled_rmse: c.sampled_rmse,
                        t_bound: c.student_t_bound,
                        per_frame_bound: c.per_frame_bound,
                        delta: job.delta,
                        resolution: g.width,
                    });
                }
            }
        }
        log(&format!(
            "{}: {} measured {measured:.5}",
            scene.name,
            method.label()
        ));
    }
    Ok(rows)
}

fn rmse(v: &[f32], truth: &[f32], mask: &[bool]) -> f64 {
    let (sum, n) = v.iter().zip(truth).zip(mask).filter(|(_, m)| **m).fold(
        (0.0f64, 0usize),
        |(s, n), ((a, b), _)| {
            let d = f64::from(a.clamp(0.0, 1.0)) - f64::from(*b);
            (s + d * d, n + 1)
        },
    );
    (sum / n.max(1) as f64).sqrt()
}

/// Coverage and sharpness of one group of draws.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    pub half: String,
    pub proxy: String,
    pub pixels: usize,
    pub bound: String,
    pub draws: usize,
    /// Share of draws whose bound is at least the measured RMSE.
    pub coverage: f64,
    /// Median bound / measured (draws of a frame with error).
    pub median_ratio: f64,
    /// The (scene, method) whose draws the bound covered least, and how many of its draws.
    pub worst: String,
    pub worst_coverage: f64,
}

/// The halves as the summary groups them: the checking half and the held-out scenes are both
/// scenes the fit never saw.
pub fn group(half: &str) -> &'static str {
    if half == Half::Fitting.name() {
        "fitting"
    } else {
        "checking + held out"
    }
}

/// Per (half, proxy, K, bound): coverage, median ratio, the worst (scene, method).
pub fn summarize(rows: &[Row], stretch: f64) -> Vec<Summary> {
    let mut keys: Vec<(&'static str, String, usize)> = rows
        .iter()
        .map(|r| (group(&r.half), r.proxy.clone(), r.pixels))
        .collect();
    keys.sort();
    keys.dedup();
    let mut out = Vec::new();
    for (g, proxy, k) in keys {
        for kind in [BoundKind::Calibrated, BoundKind::PerFrame] {
            let draws: Vec<&Row> = rows
                .iter()
                .filter(|r| group(&r.half) == g && r.proxy == proxy && r.pixels == k)
                .collect();
            let covered = |r: &Row| r.bound(kind, stretch) >= r.core.rmse;
            let ratios: Vec<f64> = draws
                .iter()
                .filter(|r| r.core.rmse > 0.0)
                .map(|r| r.bound(kind, stretch) / r.core.rmse)
                .collect();
            let mut per_row: Vec<(String, f64)> = Vec::new();
            let mut pairs: Vec<(String, String)> = draws
                .iter()
                .map(|r| (r.core.scene.clone(), r.core.spec.clone()))
                .collect();
            pairs.sort();
            pairs.dedup();
            for (s, m) in pairs {
                let mine: Vec<&&Row> = draws
                    .iter()
                    .filter(|r| r.core.scene == s && r.core.spec == m)
                    .collect();
                per_row.push((
                    format!("{m} on {s}"),
                    mine.iter().filter(|r| covered(r)).count() as f64 / mine.len() as f64,
                ));
            }
            let worst = per_row
                .iter()
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .cloned()
                .unwrap_or_default();
            out.push(Summary {
                half: g.to_string(),
                proxy: proxy.clone(),
                pixels: k,
                bound: match kind {
                    BoundKind::Calibrated => format!("calibrated (t × {stretch:.2})"),
                    BoundKind::PerFrame => "per-frame".into(),
                },
                draws: draws.len(),
                coverage: draws.iter().filter(|r| covered(r)).count() as f64
                    / draws.len().max(1) as f64,
                median_ratio: crate::record::stats::median(&ratios).unwrap_or(f64::NAN),
                worst: worst.0,
                worst_coverage: worst.1,
            });
        }
    }
    out
}

/// The least stretch (to 0.01) of the t bound covering [`FIT_COVERAGE`] of the fitting half's
/// draws at K = [`FIT_PIXELS`] under `proxy`, as split conformal prediction takes it: the
/// ⌈(n + 1)·0.95⌉-th smallest ratio measured / t bound. None without fitting draws.
pub fn fit_stretch(rows: &[Row], proxy: &str) -> Option<f64> {
    let mut ratios: Vec<f64> = rows
        .iter()
        .filter(|r| r.half == Half::Fitting.name() && r.proxy == proxy && r.pixels == FIT_PIXELS)
        .map(|r| {
            if r.t_bound > 0.0 {
                r.core.rmse / r.t_bound
            } else if r.core.rmse > 0.0 {
                f64::INFINITY
            } else {
                0.0
            }
        })
        .collect();
    if ratios.is_empty() {
        return None;
    }
    ratios.sort_by(f64::total_cmp);
    let rank = (((ratios.len() + 1) as f64) * FIT_COVERAGE).ceil() as usize;
    let r = ratios[rank.min(ratios.len()) - 1];
    Some((r * 100.0).ceil() / 100.0)
}

/// The summary as a Markdown table.
pub fn markdown(summary: &[Summary]) -> String {
    let mut s = String::from("| half | proxy | K | bound | draws | coverage | median bound/measured | worst (its coverage) |\n|---|---|---:|---|---:|---:|---:|---|\n");
    for l in summary {
        s += &format!(
            "| {} | {} | {} | {} | {} | {:.1}% | {:.3} | {} ({:.0}%) |\n",
            l.half,
            l.proxy,
            l.pixels,
            l.bound,
            l.draws,
            100.0 * l.coverage,
            l.median_ratio,
            l.worst,
            100.0 * l.worst_coverage
        );
    }
    s
}

/// The study's files: the rows, the summary at the engine's stretch, and the fit.
pub fn files(rows: &[Row]) -> Result<Vec<(String, Vec<u8>)>> {
    let summary = summarize(rows, bound::STRETCH);
    let fits: Vec<String> = PROXIES
        .iter()
        .map(|p| {
            format!(
                "{}: {}",
                p.name(),
                fit_stretch(rows, p.name())
                    .map_or("no fitting draws".into(), |s| format!("{s:.2}"))
            )
        })
        .collect();
    let md = format!(
        "{}\nStretch fitted on the fitting half at K = {FIT_PIXELS} ({:.0}% of its draws): {}; the engine's is {:.2}.\n",
        markdown(&summary),
        100.0 * FIT_COVERAGE,
        fits.join(", "),
        bound::STRETCH
    );
    let json = serde_json::to_vec_pretty(&summary)
        .map_err(|e| Error::io_text("summary.json".into(), e.to_string()))?;
    Ok(vec![
        ("certify.csv".into(), csv(rows).into_bytes()),
        ("summary.md".into(), md.into_bytes()),
        ("summary.json".into(), json),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(half: &str, method: &str, draw: u32, measured: f64, t: f64) -> Row {
        Row {
            core: RowCore {
                scene: "s".into(),
                spec: method.into(),
                method: method.into(),
                rmse: measured,
                ..RowCore::default()
            },
            half: half.into(),
            proxy: "band".into(),
            pixels: FIT_PIXELS,
            draw,
            unique_pixels: 2000,
            sampled_rmse: t * 0.9,
            t_bound: t,
            per_frame_bound: 0.1,
            delta: 0.05,
            resolution: 128,
        }
    }

    #[test]
    fn the_stretch_is_the_conformal_quantile_of_the_fitting_ratios() {
        // 19 fitting draws with ratios 0.81 … 0.99 and one at 1.30: the split-conformal rank
        // ⌈(20 + 1) · 0.95⌉ = 20, the largest (the plain ⌈20 · 0.95⌉ = 19th would say 0.99).
        let mut rows: Vec<Row> = (0..19)
            .map(|i| row("fitting", "m", i, 0.81 + 0.01 * i as f64, 1.0))
            .collect();
        rows.push(row("fitting", "m", 19, 1.3, 1.0));
        rows.push(row("checking", "m", 0, 9.0, 1.0));
        assert_eq!(fit_stretch(&rows, "band"), Some(1.3));
        // With 39 draws the rank is ⌈40 · 0.95⌉ = 38: the outlier is left out.
        let many: Vec<Row> = (0..38)
            .map(|i| row("fitting", "m", i, 0.6 + 0.01 * i as f64, 1.0))
            .chain([row("fitting", "m", 38, 1.3, 1.0)])
            .collect();
        assert_eq!(fit_stretch(&many, "band"), Some(0.97));
        assert_eq!(fit_stretch(&rows, "second-opinion"), None);
        let s = summarize(&rows, 1.0);
        let fit = s
            .iter()
            .find(|l| l.half == "fitting" && l.bound.starts_with("calibrated"))
            .unwrap();
        assert_eq!(fit.draws, 20);
        assert!(
            (fit.coverage - 19.0 / 20.0).abs() < 1e-12,
            "{}",
            fit.coverage
        );
        let check = s
            .iter()
            .find(|l| l.half == "checking + held out" && l.bound.starts_with("calibrated"))
            .unwrap();
        assert_eq!((check.coverage, check.worst_coverage), (0.0, 0.0));
        assert_eq!(parse_csv(&csv(&rows)).unwrap(), rows);
    }

    /// The committed rows (written before the core: the label in `method`, `measured_rmse`)
    /// read, and give the committed summary and fit, byte for byte.
    #[test]
    fn the_committed_rows_read_and_give_the_committed_summary() {
        let dir =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../results/certify-coverage");
        let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
        let rows = parse_csv(&read("certify.csv")).unwrap();
        assert_eq!(rows.len(), 4380);
        let first = &rows[0].core;
        assert_eq!(
            (
                first.scene.as_str(),
                first.spec.as_str(),
                first.method.as_str()
            ),
            ("analytic-square", "hard", "hard")
        );
        assert_eq!(first.rmse, 0.1074769045732458);
        assert!(rows
            .iter()
            .any(|r| r.core.spec == "regular:n=5,layout=centred" && r.core.method == "regular"));
        let files = files(&rows).unwrap();
        assert_eq!(String::from_utf8_lossy(&files[1].1), read("summary.md"));
        assert_eq!(String::from_utf8_lossy(&files[2].1), read("summary.json"));
        // Written again with the core first, they read back the same.
        assert_eq!(parse_csv(&csv(&rows)).unwrap(), rows);
    }
}
