//! `penumbra estimate` (docs/error-estimate.md §5): the error estimate checked against the truth.
//! For each scene and grid setting one frame with `estimate = on`; its predicted RMSE against the
//! RMSE measured with the continuous reference, its per-pixel bound against the true error, and
//! its split against the maps' own error (V against the exact visibility at the grid's own
//! points: the lattice reference for `regular:n=17`, else the mean of the point references).

pub(crate) mod charts;
pub mod command;

use self::charts::{estimate_svg, EstimatePoint};
use crate::frame::{FrameOptions, Renderer};
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::fixed_samples::{regular_points, FixedBuffers, Layout};
use crate::methods::{estimate, Method};
use crate::record::judge::Judge;
use crate::record::RowCore;
use crate::reference::truth::{self, Cache};
use crate::reference::ReferenceMode;
use crate::report::charts::svg_to_png;
use crate::scene::Scene;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};

/// The six settings of the check: centred grids from 9 to 81 maps at two map sizes, the lattice
/// and the jittered grid (spec without `estimate`, map size).
pub const DEFAULT_SETTINGS: [(&str, u32); 6] = [
    ("regular:n=3,layout=centred", 512),
    ("regular:n=5,layout=centred", 512),
    ("regular:n=5,layout=centred", 1024),
    ("regular:n=9,layout=centred", 1024),
    ("regular:n=17", 512),
    ("regular:n=8,layout=jittered", 512),
];

/// The band a frame's predicted/measured ratio must fall in (issue 23).
pub const RATIO_BAND: (f64, f64) = (0.8, 1.25);

/// One setting: a `regular` spec and a map size.
#[derive(Clone, Debug)]
pub struct Setting {
    pub spec: String,
    pub map_size: u32,
}

impl Setting {
    /// `SPEC@SIZE`, e.g. `regular:n=5,layout=centred@1024`.
    pub fn parse(text: &str) -> Result<Setting> {
        let bad = |why: &str| {
            Error::param(format!(
                "--settings `{text}`: {why}; give SPEC@SIZE, e.g. regular:n=5,layout=centred@1024"
            ))
        };
        let (spec, size) = text.rsplit_once('@').ok_or_else(|| bad("no @SIZE"))?;
        let map_size: u32 = size
            .parse()
            .ok()
            .filter(|s| (16..=8192).contains(s))
            .ok_or_else(|| bad("SIZE is not a map size in 16..=8192"))?;
        let method = Method::parse(spec, &[]).map_err(|e| bad(&e.to_string()))?;
        // The study adds `estimate=on` itself; a spec that sets it either way would be quoted
        // back later as `…,estimate=off,estimate=on`, a spec nobody wrote.
        if spec.split_once(':').is_some_and(|(_, params)| {
            params
                .split(',')
                .any(|kv| kv.split('=').next().is_some_and(|k| k.trim() == "estimate"))
        }) {
            return Err(bad(
                "`estimate` is set by the study (estimate = on is added); leave it out of the spec",
            ));
        }
        if method.name() != "regular" || method.params_json()["cull"] == true {
            return Err(bad(
                "the estimate is built for `regular` grids (without cull; estimate = on is added)",
            ));
        }
        if method.params_json()["n"] == 1 {
            return Err(bad("n = 1 has no half sets to compare"));
        }
        Ok(Setting {
            spec: spec.to_string(),
            map_size,
        })
    }

    /// What makes two settings the same: the method's label (presets and defaults spelled out)
    /// and the map size.
    pub fn key(&self) -> (String, u32) {
        (
            Method::parse(&self.spec, &[]).map_or_else(|_| self.spec.clone(), |m| m.label()),
            self.map_size,
        )
    }
}

/// One line of `estimate.jsonl`: one (scene, setting) pair.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EstimateLine {
    /// Scene, the setting's spec (without `estimate=on`), method and params (with it), maps, map
    /// size, the measured RMSE, adapter, build; `frame_ms` 0: the study times no frame (its
    /// files stay the same from run to run).
    #[serde(flatten)]
    pub core: RowCore,
    pub layout: String,
    pub predicted_rmse: f64,
    pub predicted_sampling: f64,
    pub predicted_map: f64,
    /// The maps' part's quantization and bias terms (m² = Q² + B²).
    #[serde(default)]
    pub predicted_quantization: f64,
    #[serde(default)]
    pub predicted_bias: f64,
    /// The maps' part that averages out over samples (`Prediction::predicted_map_averaging`).
    #[serde(default)]
    pub predicted_map_averaging: f64,
    /// predicted / measured, and whether it lies in RATIO_BAND.
    pub ratio: f64,
    pub within: bool,
    /// Share of geometry pixels whose |V − reference| is at most the bound.
    pub bound_coverage: f64,
    /// V against the exact visibility at the grid's points (the maps' error), and that against
    /// the continuous reference (the sampling error); `exact` names the reference used.
    pub measured_map: f64,
    pub measured_sampling: f64,
    pub exact: String,
    pub resolution: [u32; 2],
    pub reference: String,
    /// A setting that failed at run time: the reason (its figures are zero and mean nothing; the
    /// summary and the chart skip it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
}

impl EstimateLine {
    /// What is wrong with a row read back (`calibrate --estimates`), as `key = value: why`: its
    /// errors of V lie in [0, 1] (the measured one above 0: a ratio to it is the point of the row),
    /// its predictions are finite and not negative, and it has maps of some size. Failed rows are
    /// not read.
    pub fn check(&self) -> Option<String> {
        use crate::record::row::shown;
        if self.failed.is_some() {
            return None;
        }
        if !(self.core.rmse > 0.0 && self.core.rmse <= 1.0) {
            return Some(format!("rmse = {}: an RMSE of V lies in (0, 1] (a pair with no error has no ratio to calibrate)", shown(self.core.rmse)));
        }
        for (key, v) in [
            ("measured_map", self.measured_map),
            ("measured_sampling", self.measured_sampling),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return Some(format!("{key} = {}: an RMSE of V lies in [0, 1]", shown(v)));
            }
        }
        let predictions = [
            ("predicted_rmse", self.predicted_rmse),
            ("predicted_sampling", self.predicted_sampling),
            ("predicted_map", self.predicted_map),
            ("predicted_quantization", self.predicted_quantization),
            ("predicted_bias", self.predicted_bias),
            ("predicted_map_averaging", self.predicted_map_averaging),
        ];
        for (key, v) in predictions {
            if !(v.is_finite() && v >= 0.0) {
                return Some(format!(
                    "{key} = {}: a predicted RMSE is a finite number, at least 0",
                    shown(v)
                ));
            }
        }
        if self.predicted_sampling.hypot(self.predicted_map) == 0.0 {
            return Some("predicted_sampling = 0 and predicted_map = 0: a prediction of no error has nothing to calibrate".into());
        }
        if self.core.map_size == 0 || self.core.maps == 0 {
            return Some(format!(
                "map_size = {}, maps = {}: a setting has at least one map of at least one texel",
                self.core.map_size, self.core.maps
            ));
        }
        None
    }
}

fn rms(a: &[f32], b: &[f32], mask: &[bool]) -> f64 {
    let (sum, n) = a.iter().zip(b).zip(mask).filter(|(_, m)| **m).fold(
        (0.0f64, 0usize),
        |(s, n), ((x, y), _)| {
            let d = f64::from(*x) - f64::from(*y);
            (s + d * d, n + 1)
        },
    );
    (sum / n.max(1) as f64).sqrt()
}

/// The exact visibility at the grid's own points, and its name.
fn exact_reference(
    scene: &Scene,
    g: &crate::render::gbuffer::GBufferCpu,
    n: u32,
    layout: Layout,
) -> Result<(Vec<f32>, String)> {
    if n == 17 && layout == Layout::Lattice {
        let image = truth::compute(scene, g, ReferenceMode::Lattice, &Cache::default_for(false))?;
        return Ok((image.values, "lattice".into()));
    }
    let points = regular_points(n, layout);
    // Not cached: hundreds of one-point images would fill the cache for one study.
    let modes: Vec<ReferenceMode> = points
        .iter()
        .map(|&(s, t)| ReferenceMode::Point { s, t })
        .collect();
    let mut mean = vec![0.0f32; g.position.len()];
    for image in truth::trace_modes(scene, g, &modes)? {
        for (m, v) in mean.iter_mut().zip(image) {
            *m += v / points.len() as f32;
        }
    }
    Ok((mean, format!("mean of {} point references", points.len())))
}

/// Runs every setting on `scene` (loaded with `sets`; each setting adds its map size).
pub fn run_scene(
    ctx: &GpuContext,
    name: &str,
    sets: &[(String, String)],
    settings: &[Setting],
    mode: ReferenceMode,
    cache: &Cache,
    log: &dyn Fn(&str),
) -> Result<Vec<EstimateLine>> {
    let base = Scene::load(name, sets)?;
    let (g, reference) = truth::for_scene(ctx, &base, mode, cache)?;
    let judge = Judge::new(&base, &g, reference.values.clone());
    let mask: Vec<bool> = (0..g.position.len()).map(|i| g.is_geometry(i)).collect();
    let mut lines = Vec::new();
    let run = Run {
        ctx,
        name,
        sets,
        mask: &mask,
        judge: &judge,
        g: &g,
        reference: &reference,
    };
    for setting in settings {
        // A setting that fails is a line that says why; the others go on.
        let line = run.setting(setting).unwrap_or_else(|e| {
            let line = EstimateLine::failed(&base.name, setting, &run, e.to_string());
            log(&crate::record::failed_line(
                &format!(
                    "{} {} @{}",
                    line.core.scene, line.core.spec, line.core.map_size
                ),
                &e.to_string(),
            ));
            line
        });
        if line.failed.is_none() {
            log(&format!(
                "{} {} @{}: measured {:.5}, predicted {:.5} ({:.2}×), bound covers {:.1}%",
                line.core.scene,
                line.core.spec,
                line.core.map_size,
                line.core.rmse,
                line.predicted_rmse,
                line.ratio,
                100.0 * line.bound_coverage
            ));
        }
        lines.push(line);
    }
    Ok(lines)
}

/// What every setting of one scene shares.
struct Run<'a> {
    ctx: &'a GpuContext,
    name: &'a str,
    sets: &'a [(String, String)],
    mask: &'a [bool],
    judge: &'a Judge,
    g: &'a crate::render::gbuffer::GBufferCpu,
    reference: &'a truth::ReferenceImage,
}

impl Run<'_> {
    /// One setting: rendered, predicted and measured.
    fn setting(&self, setting: &Setting) -> Result<EstimateLine> {
        let Run {
            ctx,
            name,
            sets,
            mask,
            judge,
            g,
            reference,
        } = *self;
        let mut with_size = sets.to_vec();
        with_size.push(("shadow_map_size".into(), setting.map_size.to_string()));
        let scene = Scene::load(name, &with_size)?;
        let method = Method::parse(&format!("{},estimate=on", setting.spec), &[])?;
        let mut renderer = Renderer::new(ctx, &scene, &method)?;
        let f = renderer.frame(FrameOptions {
            mode: TimingMode::Frame,
            pictures: false,
        })?;
        let kept: FixedBuffers = renderer
            .inspect()?
            .ok_or_else(|| Error::limit(format!("{}: no estimate sums", method.label())))?;
        let params = method.params_json();
        let layout = match params["layout"].as_str() {
            Some("centred") => Layout::Centred,
            Some("jittered") => Layout::Jittered,
            _ => Layout::Lattice,
        };
        let n = params["n"].as_u64().unwrap_or(1) as u32;
        let (p, bound) = estimate::predict(&kept.estimate_sums, mask, layout, n)?;
        let measured = judge.judge(&scene, &method.label(), &f)?.metrics.rmse;
        let covered = (0..mask.len())
            .filter(|&i| mask[i] && (f.visibility[i] - reference.values[i]).abs() <= bound[i])
            .count();
        let (exact, exact_name) = exact_reference(&scene, g, n, layout)?;
        let ratio = p.predicted_rmse / measured.max(1e-12);
        Ok(EstimateLine {
            core: RowCore {
                maps: f.output.shadow_maps,
                map_size: setting.map_size,
                rmse: measured,
                adapter: format!("{} ({})", ctx.summary.name, ctx.summary.backend).into(),
                ..RowCore::of(&scene.name, &setting.spec, &method)
            },
            layout: params["layout"].as_str().unwrap_or("lattice").to_string(),
            predicted_rmse: p.predicted_rmse,
            predicted_sampling: p.predicted_sampling,
            predicted_map: p.predicted_map,
            predicted_quantization: p.predicted_quantization,
            predicted_bias: p.predicted_bias,
            predicted_map_averaging: p.predicted_map_averaging,
            ratio,
            within: (RATIO_BAND.0..=RATIO_BAND.1).contains(&ratio),
            bound_coverage: covered as f64 / judge.geometry_pixels().max(1) as f64,
            measured_map: rms(&f.visibility, &exact, mask),
            measured_sampling: rms(&exact, &reference.values, mask),
            exact: exact_name,
            resolution: [scene.render.width, scene.render.height],
            reference: truth::mode_label(&reference.mode),
            failed: None,
        })
    }
}

impl EstimateLine {
    /// The line of a setting that failed: what it was and why, no figures.
    fn failed(scene: &str, setting: &Setting, run: &Run, reason: String) -> EstimateLine {
        EstimateLine {
            core: RowCore {
                map_size: setting.map_size,
                adapter: format!("{} ({})", run.ctx.summary.name, run.ctx.summary.backend).into(),
                ..RowCore::of_spec(scene, &setting.spec)
            },
            layout: String::new(),
            predicted_rmse: 0.0,
            predicted_sampling: 0.0,
            predicted_map: 0.0,
            predicted_quantization: 0.0,
            predicted_bias: 0.0,
            predicted_map_averaging: 0.0,
            ratio: 0.0,
            within: false,
            bound_coverage: 0.0,
            measured_map: 0.0,
            measured_sampling: 0.0,
            exact: String::new(),
            resolution: [run.g.width, run.g.height],
            reference: truth::mode_label(&run.reference.mode),
            failed: Some(reason),
        }
    }
}

/// `estimate.jsonl`, `estimate.md`, `charts/estimate.svg`/`.png` and `report.html`, as one set.
pub fn files(lines: &[EstimateLine]) -> Result<Vec<(String, Vec<u8>)>> {
    let mut jsonl = String::new();
    for l in lines {
        jsonl += &serde_json::to_string(l)
            .map_err(|e| Error::io_text("estimate.jsonl".into(), e.to_string()))?;
        jsonl.push('\n');
    }
    let points: Vec<EstimatePoint> = lines
        .iter()
        .filter(|l| l.failed.is_none())
        .map(|l| EstimatePoint {
            layout: l.layout.clone(),
            label: format!(
                "{} {}@{}",
                l.core.scene,
                short(&l.core.spec),
                l.core.map_size
            ),
            measured: l.core.rmse,
            predicted: l.predicted_rmse,
        })
        .collect();
    let svg = estimate_svg(&points)?;
    let md = markdown(lines);
    let html = crate::report::md_page::page(
        "Error estimate against the truth",
        &md,
        &[("Predicted against measured RMSE", &svg)],
    );
    Ok(vec![
        ("estimate.jsonl".to_string(), jsonl.into_bytes()),
        ("estimate.md".to_string(), md.into_bytes()),
        ("charts/estimate.png".to_string(), svg_to_png(&svg, 1.0)?),
        ("charts/estimate.svg".to_string(), svg.into_bytes()),
        ("report.html".to_string(), html.into_bytes()),
    ])
}

/// Which part limits the count in RATIO_BAND: each part's own predicted/measured ratio in the
/// band, and the total's count with the measured sampling error, the measured maps' error, or
/// both in place of the predictions (added in quadrature as the prediction is).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PartLimits {
    pub sampling_within: usize,
    pub map_within: usize,
    pub with_measured_sampling: usize,
    pub with_measured_map: usize,
    pub with_both_measured: usize,
}

pub fn part_limits(lines: &[EstimateLine]) -> PartLimits {
    let within = |x: f64, y: f64| (RATIO_BAND.0..=RATIO_BAND.1).contains(&(x / y.max(1e-12)));
    let count = |f: &dyn Fn(&EstimateLine) -> bool| lines.iter().filter(|l| f(l)).count();
    PartLimits {
        sampling_within: count(&|l| within(l.predicted_sampling, l.measured_sampling)),
        map_within: count(&|l| within(l.predicted_map, l.measured_map)),
        with_measured_sampling: count(&|l| {
            within(l.measured_sampling.hypot(l.predicted_map), l.core.rmse)
        }),
        with_measured_map: count(&|l| {
            within(l.predicted_sampling.hypot(l.measured_map), l.core.rmse)
        }),
        with_both_measured: count(&|l| {
            within(l.measured_sampling.hypot(l.measured_map), l.core.rmse)
        }),
    }
}

/// `regular:n=5,layout=centred` → `n=5 centred`.
fn short(spec: &str) -> String {
    spec.trim_start_matches("regular:").replace(",layout=", " ")
}

/// The summary (pairs in the band, pixels covered) and one row per pair.
pub fn markdown(all: &[EstimateLine]) -> String {
    // The summary is of the measured pairs; the failed ones are counted and listed with their reason.
    let lines: &[EstimateLine] = &all
        .iter()
        .filter(|l| l.failed.is_none())
        .cloned()
        .collect::<Vec<_>>();
    let failed = all.len() - lines.len();
    let Some(first) = lines.first().or(all.first()) else {
        return "# Error estimate against the truth\n\nNo pairs.\n".into();
    };
    let within = lines.iter().filter(|l| l.within).count();
    let covered = lines.iter().filter(|l| l.bound_coverage >= 0.9).count();
    let limits = part_limits(lines);
    let mut s = format!(
        "# Error estimate against the truth\n\n{} (scene, setting) pairs; {}x{} screen; reference {}; {}.\n\n\
         - predicted/measured RMSE in [{}, {}]: {} of {} pairs ({:.0}%);\n\
         - the per-pixel bound covers the true error on at least 90% of geometry pixels: {} of {} pairs;\n\
         - which part limits it: the sampling part's own ratio is in the band on {} pairs and the maps' on {}; \
         with the measured sampling error in place of its prediction, the total is in the band on {}, with the measured \
         maps' error on {}, with both (the measured parts' squares added) on {}.\n\n",
        lines.len(),
        first.resolution[0],
        first.resolution[1],
        first.reference,
        first.core.adapter,
        RATIO_BAND.0,
        RATIO_BAND.1,
        within,
        lines.len(),
        100.0 * within as f64 / lines.len() as f64,
        covered,
        lines.len(),
        limits.sampling_within,
        limits.map_within,
        limits.with_measured_sampling,
        limits.with_measured_map,
        limits.with_both_measured
    );
    if failed > 0 {
        s += &format!("{failed} of {} settings failed (\"failed: reason\" below); the figures above are of the other {}.\n\n", all.len(), lines.len());
    }
    s += "| scene | setting | maps | measured | predicted | ratio | bound covers | sampling: predicted / measured | maps: predicted / measured |\n";
    s += "|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for l in all {
        if let Some(reason) = &l.failed {
            s += &format!(
                "| {} | {} @{} | failed: {} | | | | | | |\n",
                l.core.scene,
                short(&l.core.spec),
                l.core.map_size,
                reason.replace('|', "\\|")
            );
            continue;
        }
        s += &format!(
            "| {} | {} @{} | {} | {:.5} | {:.5} | {:.2}{} | {:.1}% | {:.5} / {:.5} | {:.5} / {:.5} |\n",
            l.core.scene,
            short(&l.core.spec),
            l.core.map_size,
            l.core.maps,
            l.core.rmse,
            l.predicted_rmse,
            l.ratio,
            if l.within { "" } else { " (out)" },
            100.0 * l.bound_coverage,
            l.predicted_sampling,
            l.measured_sampling,
            l.predicted_map,
            l.measured_map
        );
    }
    s += "\nMeasured split: sampling = exact visibility at the grid's points against the continuous reference; maps = V against that exact visibility (the lattice reference for n=17, else the mean of the point references).\n";
    s
}

#[cfg(test)]
mod tests {
    use super::{part_limits, EstimateLine, PartLimits, Setting};

    fn line(measured: f64, sampling: (f64, f64), map: (f64, f64)) -> EstimateLine {
        let predicted = sampling.0.hypot(map.0);
        EstimateLine {
            core: crate::record::RowCore {
                scene: "s".into(),
                spec: "regular:n=3,layout=centred".into(),
                maps: 9,
                map_size: 512,
                rmse: measured,
                adapter: "none".into(),
                ..Default::default()
            },
            layout: "centred".into(),
            predicted_rmse: predicted,
            predicted_sampling: sampling.0,
            predicted_map: map.0,
            predicted_quantization: 0.0,
            predicted_bias: map.0,
            predicted_map_averaging: 0.0,
            ratio: predicted / measured,
            within: false,
            bound_coverage: 1.0,
            measured_map: map.1,
            measured_sampling: sampling.1,
            exact: "mean of 9 point references".into(),
            resolution: [64, 64],
            reference: "continuous 32x32".into(),
            failed: None,
        }
    }

    #[test]
    fn part_limits_count_each_substitution() {
        // (predicted, measured) sampling and maps parts; measured RMSE as given.
        let lines = [
            // Sampling read right (0.03 / 0.03), maps over-read 2×: only the measured maps' part
            // brings the total (hypot 0.03, 0.04 = 0.05) into the band.
            line(0.05, (0.03, 0.03), (0.08, 0.04)),
            // Both parts right and the total their quadrature sum: in the band every way.
            line(0.05, (0.04, 0.04), (0.03, 0.03)),
            // Both parts right, but they cancel in the frame (measured 0.035 against 0.05 added).
            line(0.035, (0.04, 0.04), (0.03, 0.03)),
            // Sampling under-read 2×, maps right: the measured sampling part fixes it.
            line(0.05, (0.02, 0.04), (0.03, 0.03)),
        ];
        assert_eq!(
            part_limits(&lines),
            PartLimits {
                sampling_within: 3,
                map_within: 3,
                with_measured_sampling: 2,
                with_measured_map: 2,
                with_both_measured: 3
            }
        );
    }

    #[test]
    fn settings_parse_and_refuse() {
        let s = Setting::parse("regular:n=5,layout=centred@1024").unwrap();
        assert_eq!(
            (s.spec.as_str(), s.map_size),
            ("regular:n=5,layout=centred", 1024)
        );
        for bad in [
            "regular:n=5",
            "regular:n=5@big",
            "regular:n=5@8",
            "hard@512",
            "regular:n=1@512",
            "regular:n=3,cull=on@512",
            "regular:n=3,estimate=on@512",
            "regular:n=3,estimate=off@512",
            "regular:n=0@512",
        ] {
            let e = Setting::parse(bad)
                .err()
                .unwrap_or_else(|| panic!("{bad} parsed"))
                .to_string();
            assert!(e.contains(bad) && e.contains("SPEC@SIZE"), "{bad}: {e}");
        }
    }
}
