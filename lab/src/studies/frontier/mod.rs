//! `penumbra frontier` (docs/frontier.md): every fixed setting of one scene (regular grids in both
//! layouts, map sizes, hybrid maps, the adaptive presets in both scopes, the single-map family)
//! measured by the one measure loop (`record::measure`, one run per map configuration), judged
//! against one reference, and the frontier of error against time: the settings no other setting
//! beats on both.

pub mod budget;
pub(crate) mod charts;
pub mod command;
pub mod files;
pub mod front;
pub mod grid;
pub mod second_look;

use crate::gpu::GpuContext;
use crate::methods::{Family, Method};
use crate::record::judge::Judge;
use crate::record::measure::{self, Phase};
use crate::record::{row_core, RowCore};
use crate::reference::truth::{self, Cache};
use crate::reference::ReferenceMode;
use crate::scene::Scene;
use crate::Result;
use serde::{Deserialize, Serialize};

pub struct FrontierJob<'a> {
    pub scene: &'a Scene,
    /// Settings grouped by map configuration (grid::settings).
    pub groups: Vec<grid::Group>,
    /// How the grid was chosen, with its axes (`Thinning::describe`).
    pub thinning: String,
    pub repeats: u32,
    pub reference: ReferenceMode,
    pub cache: Cache,
    /// `--certify K`: every setting's judged frame gets a certified bound.
    pub certify: Option<crate::certify::Options>,
    /// Fill the n list near the front and time the front and its challengers again side by
    /// side before the front is drawn (second_look.rs); off with `--no-second-look`.
    pub second_look: bool,
}

/// One line of `frontier.jsonl`: one setting.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FrontierLine {
    /// Scene, the method spec as the grid writes it, method, params, maps of the judged frame,
    /// map size (for a budget row, the size its frame rendered, `rendered_map_size`, not the
    /// group's), RMSE, median frame time, adapter, build and a budget row's target.
    #[serde(flatten)]
    pub core: RowCore,
    /// The map configuration (`plain 512`, `hybrid 2048→512`).
    pub map_config: String,
    /// `regular lattice`, `regular centred`, `adaptive global`, `adaptive local`, `single map` or
    /// `filtered maps`.
    pub kind: String,
    /// The method's label (`penumbra compare`'s name for it; a preset may be spelt out).
    pub label: String,
    /// Mean FLIP of the shaded image; `null` when not computed.
    pub flip: Option<f64>,
    /// Fastest and slowest frame over the timed frames.
    pub frame_ms_min: f64,
    pub frame_ms_max: f64,
    pub on_frontier: bool,
    /// Off the frontier: the fastest frontier setting at most as slow and at most as wrong
    /// (`spec @ map_config`).
    pub beaten_by: Option<String>,
    pub thinning: String,
    pub resolution: [u32; 2],
    pub reference: String,
    pub repeats: u32,
    pub clock: String,
    /// `hardware` or `compute`: who rasterized the setting's maps (`--set raster=auto` picks per
    /// map size, so the times of one frontier may come from both).
    #[serde(default)]
    pub raster: String,
    /// A budget row's oracle: the cheapest fixed setting whose RMSE is at most the target, what a
    /// method that knew the truth would render (`spec @ map_config`).
    #[serde(default)]
    pub oracle: Option<String>,
    /// A budget row's own reading (run.json's record): its calibrated predicted RMSE, whether it
    /// reports the target met, and its search's wall clock (the tries of the frame that chose,
    /// which the timed frames after it do not repeat).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub budget: Option<budget::Reading>,
    /// A budget row and its oracle timed side by side (`budget::pair`): what time/oracle reads.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub paired: Option<budget::Paired>,
    /// What the second look did to this setting: filled in near the front, timed again (docs/frontier.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub second_look: Option<second_look::Look>,
    /// A setting that failed at run time: the reason (its figures are zero and mean nothing; the
    /// front, the budget's rivals and the oracle skip it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
    /// `--certify K`: the certified bound on this setting's RMSE (docs/certify.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub certify: Option<crate::record::Certified>,
}

impl FrontierLine {
    /// `spec @ map_config`: a setting's name across map configurations.
    pub fn setting(&self) -> String {
        format!("{} @ {}", self.core.spec, self.map_config)
    }

    /// (frame ms, RMSE) as the front reads it: budget rows at an infinite time (they neither join
    /// nor shape the frontier), failed rows at infinite time and error (they reach nothing).
    pub fn point(&self) -> (f64, f64) {
        match (&self.failed, self.is_budget()) {
            (Some(_), _) => (f64::INFINITY, f64::INFINITY),
            (None, true) => (f64::INFINITY, self.core.rmse),
            (None, false) => (self.core.frame_ms, self.core.rmse),
        }
    }

    /// Adaptive rows, the ones the chart and the table single out.
    pub fn is_adaptive(&self) -> bool {
        self.kind.starts_with("adaptive")
    }

    /// The error budget's rows (`--budget`): measured beside the fixed settings, judged against
    /// their frontier, never on it.
    pub fn is_budget(&self) -> bool {
        self.kind == BUDGET
    }

    /// A budget row's target T: its `target`, or for a line written before that column, the
    /// method's own parse of its spec.
    pub fn target(&self) -> Option<f64> {
        self.core.target.or_else(|| {
            let m = Method::parse(&self.core.spec, &[])
                .ok()
                .filter(|m| kind(m) == BUDGET)?;
            row_core::target(&m)
        })
    }
}

/// The kind of `auto:target=T` and `regions:target=T` rows.
pub const BUDGET: &str = "error budget";

/// The map side a frame rendered, from its record: `auto` chooses its grid's size itself
/// (`chosen.map_size`) unless it renders a one-map filter, which runs at the scene's size;
/// `regions` sizes each group's maps, and its largest is the frame's. Every other method renders
/// at the scene's size (`scene_size`, the group's).
fn rendered_map_size(record: &serde_json::Value, scene_size: u32) -> u32 {
    if let Some(a) = crate::methods::auto::AutoRecord::read(record) {
        return if a.renders.is_some() {
            scene_size
        } else {
            a.chosen.map_size
        };
    }
    let size = |v: &serde_json::Value| v["map_size"].as_u64().and_then(|z| u32::try_from(z).ok());
    record["classes"]
        .as_array()
        .and_then(|cs| cs.iter().filter_map(size).max())
        .unwrap_or(scene_size)
}

fn kind(m: &Method) -> String {
    if m.name() == "auto" || m.name() == "regions" {
        return BUDGET.into();
    }
    if let Some(p) = m.adaptive_params() {
        return if p.scope == crate::methods::Scope::Local {
            "adaptive local".into()
        } else {
            "adaptive global".into()
        };
    }
    match (
        m.name(),
        m.params_json().get("layout").and_then(|v| v.as_str()),
    ) {
        ("regular", Some(layout)) => format!("regular {layout}"),
        _ => match m.family() {
            Family::Hard | Family::Pcf => "single map".into(),
            f => f.title().to_string(),
        },
    }
}

/// Marks the frontier of the fixed settings and each line's nearest frontier setting, from the
/// lines' own figures. A budget row's `beaten_by` is the cheapest fixed setting whose RMSE is at
/// most its own (what it is judged against), faster or not.
pub fn mark(lines: &mut [FrontierLine]) {
    // Budget rows get an infinite time here, so they neither join nor shape the frontier; failed
    // rows an infinite time and error, and never a place on it.
    let points: Vec<(f64, f64)> = lines.iter().map(FrontierLine::point).collect();
    let mut on = front::on_frontier(&points);
    for (o, l) in on.iter_mut().zip(lines.iter()) {
        *o &= l.failed.is_none();
    }
    let names: Vec<String> = lines.iter().map(FrontierLine::setting).collect();
    for (i, l) in lines.iter_mut().enumerate() {
        l.on_frontier = on[i] && !l.is_budget();
        if l.failed.is_some() {
            (l.oracle, l.beaten_by) = (None, None);
            continue;
        }
        l.oracle = l
            .target()
            .filter(|_| l.is_budget())
            .and_then(|t| front::cheapest_reaching(&points, t))
            .map(|j| names[j].clone());
        l.beaten_by = if l.is_budget() {
            front::cheapest_reaching(&points, l.core.rmse)
                .filter(|&j| j != i && points[j].0.is_finite())
                .map(|j| names[j].clone())
        } else if on[i] {
            None
        } else {
            front::beaten_by(&points, &on, i).map(|j| names[j].clone())
        };
    }
}

/// Measures every group (one `record::measure` run each, its scene under the group's maps) and
/// returns one line per setting, frontier marked: then takes the second look (second_look.rs),
/// which fills the n list near the front and times the front and its challengers again side by
/// side before the front is drawn. `log` gets one line per measured setting.
pub fn run(ctx: &GpuContext, job: &FrontierJob, log: &dyn Fn(&str)) -> Result<Vec<FrontierLine>> {
    let scene = job.scene;
    let (g, reference) = truth::for_scene(ctx, scene, job.reference, &job.cache)?;
    let judge = Judge::new(scene, &g, reference.values.clone());
    log(&crate::studies::compare::reference_line(
        &reference,
        judge.geometry_pixels(),
    ));
    let reference_mode = truth::mode_label(&reference.mode);
    if let Some(o) = &job.certify {
        if o.pixels > judge.geometry_pixels() {
            return Err(crate::Error::param(format!(
                "--certify {}: more than the frame's {} geometry pixels",
                o.pixels,
                judge.geometry_pixels()
            )));
        }
    }
    // One certifier for every setting: the same geometry, camera and light.
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
    let total = grid::count(&job.groups);
    let bar = crate::progress::bar(measure::frame_count(total, job.repeats), "frontier");
    let mut lines = Vec::with_capacity(total);
    for group in &job.groups {
        lines.extend(measure_group(
            ctx,
            job,
            &judge,
            &reference_mode,
            group,
            certifier.as_mut(),
            &bar,
            log,
        )?);
    }
    bar.finish_and_clear();
    if let Some(line) = crate::record::failed_summary(
        lines.iter().filter(|l| l.failed.is_some()).count(),
        lines.len(),
    ) {
        log(&line);
    }
    mark(&mut lines);
    // The fill's settings join their groups, so the budget's pairing finds them as oracles.
    let mut groups = job.groups.clone();
    if job.second_look {
        let filled = second_look::fill(&mut groups, &lines);
        let bar = crate::progress::bar(
            measure::frame_count(grid::count(&filled), job.repeats),
            "frontier fill",
        );
        for group in &filled {
            let mut added = measure_group(
                ctx,
                job,
                &judge,
                &reference_mode,
                group,
                certifier.as_mut(),
                &bar,
                log,
            )?;
            added.iter_mut().for_each(|l| {
                l.second_look = Some(second_look::Look {
                    filled: true,
                    ..Default::default()
                })
            });
            lines.extend(added);
        }
        bar.finish_and_clear();
        mark(&mut lines);
        let before: Vec<bool> = lines.iter().map(|l| l.on_frontier).collect();
        second_look::retime(ctx, job, &groups, &mut lines, log)?;
        mark(&mut lines);
        // A setting not timed again moves too when the one that kept it off slowed down.
        for (l, was_on) in lines.iter_mut().zip(before) {
            if l.on_frontier != was_on
                && l.second_look
                    .as_ref()
                    .is_none_or(|k| k.retimed_as.is_none())
            {
                l.second_look.get_or_insert_with(Default::default).was_on = was_on;
            }
        }
    }
    let job = FrontierJob {
        groups,
        thinning: job.thinning.clone(),
        cache: job.cache.clone(),
        ..*job
    };
    budget::pair(ctx, &job, &mut lines, log)?;
    Ok(lines)
}

/// One group's settings measured in the one measure loop, judged, as lines (frontier unmarked).
/// With `certifier`, each judged frame gets its certified bound too.
#[allow(clippy::too_many_arguments)]
fn measure_group(
    ctx: &GpuContext,
    job: &FrontierJob,
    judge: &Judge,
    reference: &str,
    group: &grid::Group,
    mut certifier: Option<&mut crate::frame::certify::FrameCertifier>,
    bar: &indicatif::ProgressBar,
    log: &dyn Fn(&str),
) -> Result<Vec<FrontierLine>> {
    let scene = job.scene;
    let grid::Group {
        maps,
        specs,
        methods,
    } = group;
    // eps: the hybrid study's and the seed's 0.25 (docs/hybrid.md).
    let s = maps.apply(scene, 0.25);
    let mut on_frame = |m: &Method, phase: Phase, _: &crate::frame::FrameResult| {
        bar.set_message(format!("{} {} {phase}", maps.label(), m.label()));
        bar.inc(1);
    };
    let mut records = vec![serde_json::Value::Null; methods.len()];
    let mut certified = vec![None; methods.len()];
    let mut judge_frame = |i: usize, f: &crate::frame::FrameResult| {
        records[i] = f.output.record.clone();
        if let Some(c) = certifier.as_deref_mut() {
            certified[i] = Some(crate::record::Certified::of(&c.certify(f)?));
        }
        Ok(judge.judge(&s, &methods[i].label(), f)?.metrics)
    };
    let measured = measure::measure(
        ctx,
        &s,
        methods,
        job.repeats,
        &mut on_frame,
        &mut judge_frame,
    )?;
    let mut lines = Vec::with_capacity(methods.len());
    for ((((m, spec), r), record), certified) in methods
        .iter()
        .zip(specs)
        .zip(measured)
        .zip(&records)
        .zip(certified)
    {
        // A setting that failed is a line that says why; the others go on.
        let (r, failed) = match r {
            Ok(r) => (r, None),
            Err(reason) => (
                measure::Measured {
                    timing: measure::Timing::none(),
                    judged: Default::default(),
                },
                Some(reason),
            ),
        };
        let line = FrontierLine {
            core: RowCore {
                maps: r.timing.shadow_maps,
                map_size: rendered_map_size(record, s.render.shadow_map_size),
                rmse: r.judged.rmse,
                frame_ms: r.timing.median_ms,
                adapter: format!("{} ({})", ctx.summary.name, ctx.summary.backend).into(),
                ..RowCore::of(&scene.name, spec, m)
            },
            map_config: maps.label(),
            kind: kind(m),
            label: m.label(),
            flip: Some(r.judged.flip_mean).filter(|f| f.is_finite()),
            frame_ms_min: r.timing.min_ms,
            frame_ms_max: r.timing.max_ms,
            on_frontier: false,
            beaten_by: None,
            thinning: job.thinning.clone(),
            resolution: [scene.render.width, scene.render.height],
            reference: reference.to_string(),
            repeats: job.repeats,
            clock: crate::record::CLOCK.to_string(),
            raster: r.timing.raster.to_string(),
            oracle: None,
            budget: (m.name() == "auto" && failed.is_none()).then(|| budget::Reading::of(record)),
            paired: None,
            second_look: None,
            certify: certified.filter(|_| failed.is_none()),
            failed,
        };
        crate::progress::suspend(|| match &line.failed {
            Some(reason) => log(&crate::record::failed_line(&line.setting(), reason)),
            None => log(&format!(
                "{}: {} maps, median {:.1} ms, RMSE {:.4}",
                line.setting(),
                line.core.maps,
                line.core.frame_ms,
                line.core.rmse
            )),
        });
        lines.push(line);
    }
    Ok(lines)
}

#[cfg(test)]
mod tests {
    use super::rendered_map_size;
    use serde_json::json;

    /// auto's record of a frame that chose grid (n, size), rendering `renders` instead if given.
    fn auto(n: u32, size: u32, renders: Option<&str>) -> serde_json::Value {
        use crate::methods::auto::{AutoRecord, Chosen, MapCost};
        AutoRecord {
            method: "auto".into(),
            chosen: Chosen::centred((n, size)),
            target: 0.02,
            target_met: true,
            tries: Vec::new(),
            predicted_rmse: 0.01,
            predicted_sampling: 0.01,
            predicted_map: 0.0,
            certified: None,
            map_cost: MapCost {
                model: "texels".into(),
                per_map: Default::default(),
                pricing_ms: 0.0,
            },
            filter: None,
            renders: renders.map(String::from),
            maps_rendered: n * n,
            estimated: true,
            kept: false,
            warning: None,
        }
        .to_value()
        .unwrap()
    }

    #[test]
    fn a_budget_row_records_the_map_size_its_frame_rendered() {
        // auto's grid at its own size, under a group of 512² maps.
        assert_eq!(rendered_map_size(&auto(3, 2048, None), 512), 2048);
        // auto rendering a one-map filter: the scene's size, though the grid it checked was larger.
        assert_eq!(rendered_map_size(&auto(5, 1024, Some("pcss")), 512), 512);
        // regions: its largest group's maps.
        let regions =
            json!({ "classes": [{ "map_size": 368 }, { "map_size": 1456 }, { "map_size": 1024 }] });
        assert_eq!(rendered_map_size(&regions, 512), 1456);
        // A fixed setting's record says nothing of sizes: the group's.
        assert_eq!(rendered_map_size(&json!({ "shadow_maps": 9 }), 1024), 1024);
        assert_eq!(rendered_map_size(&serde_json::Value::Null, 256), 256);
    }
}
