//! `certify = on`: `regions` decides by measured error (docs/regions.md, "Certified classes").
//!
//! The plan (the classes' samples and map sides from the blocker search) is a guess that can
//! under-count a class's penumbra. So after the plan, each class's RMSE of V is bounded with the
//! exact truth at `pixels` pixels drawn within the class (its tiles' geometry pixels the design's
//! subset, `certify`), one trace for every class:
//! - a one-map filter (`pcss`, rendered once over the frame first) is kept for each class where
//!   its bound fits the frame's budget: the classes share T² by their pixels, so a class may stay
//!   over T where the others leave room (`filter_split`); where it is kept for every class, the
//!   frame is the filter;
//! - the other classes' plan is priced against the frame-wide grid (the top class's samples on
//!   every tile, one window, `Group` cost); where the grid costs at most `fallback` times the
//!   plan, the frame takes the grid and says so;
//! - while the frame's bound is over T, the classes over T that hold most of the excess are
//!   stepped up (more samples, a finer map, on its own window; a filter class to its plan), as
//!   many as the step model predicts the budget needs (`step_round`), and measured again with
//!   the same draws, until the frame's bound is at most T or their ladders end.
//!
//! Each class's bound is over its own pixels at confidence 1 − δ/C (C classes), so by the union
//! bound the frame's MSE is at most Σ_c (N_c/N) b_c² with probability 1 − δ. The frame is `met`
//! only where that bound is at most T. The truth's trace is timed as its own stage
//! (`truth_trace`) inside the frame: the measurement's cost is part of the frame's time.

use super::{ClassRecord, Group, State, LADDER};
use crate::certify::bound::BoundKind;
use crate::certify::design::{self, Design};
use crate::certify::truth::{self, TruthTracer};
use crate::certify::{self, Certificate, Sampled};
use crate::gpu::timing::StageTimer;
use crate::gpu::{readback, Stage};
use crate::methods::auto::filter::{read_v, Candidates};
use crate::methods::Method;
use crate::render::kept_maps::ReuseCounts;
use crate::stages::shade::{TILE, TILE_LIST_HEADER};
use crate::stages::FrameGpu;
use crate::Result;

/// What `certify = on` keeps from frame to frame: the truth tracer and the filter's state.
pub(super) struct Certifying {
    tracer: TruthTracer,
    filter: Option<Candidates>,
}

/// How a class is shaded in the end.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Setting {
    /// A centred grid of n × n samples on maps of `size`, over the class's own window.
    Grid { n: u32, size: u32 },
    /// The one-map filter's V.
    Filter,
}

/// One class's measurement, as the record keeps it.
#[derive(Clone, Debug, serde::Serialize)]
struct ClassMeasure {
    class: u32,
    /// `pcss`, or `regular:n=N,layout=centred @ SIZE`.
    setting: String,
    /// Step-ups after the plan (0: the plan, or the filter, was certified).
    steps: u32,
    /// The bound on the class's RMSE at confidence 1 − δ/C, and the sampled RMSE.
    bound: f64,
    sampled_rmse: f64,
    certified: bool,
    /// The bound of each setting tried, in order.
    tried: Vec<(String, f64)>,
    /// Geometry pixels in the class (N_c) and their share of the frame's.
    pixels: usize,
    share: f64,
}

/// A class being measured: its mask, its design and draws, and where it stands.
struct Class {
    class: usize,
    mask: Vec<bool>,
    design: Design,
    sampled: Option<Sampled>,
    kind: BoundKind,
    setting: Setting,
    /// The plan's grid for the class (where a filter class steps to).
    plan: Setting,
    /// The class alone: its own window and texel need (for steps); its plan's predicted cost.
    own: Group,
    plan_cost: f64,
    best: Option<(Setting, Certificate, Vec<f32>)>,
    tried: Vec<(String, f64)>,
    steps: u32,
    /// The bound of its current setting (the last measured).
    current: f64,
    /// Its ladder ended: no finer setting is left, or the steps stopped paying (below).
    exhausted: bool,
    /// A step of samples bought under a quarter of what the model predicted: the class's error
    /// is not its samples', so its next rungs are finer maps; one of those failing too ends it.
    texels: bool,
}

fn label(s: Setting) -> String {
    match s {
        Setting::Grid { n, size } => format!("regular:n={n},layout=centred @ {size}"),
        Setting::Filter => "pcss".into(),
    }
}

/// sqrt(Σ_c N_c/N · b_c²) over the classes' best bounds so far (1 where a class has none).
fn frame_bound(classes: &[Class], geometry_pixels: usize) -> f64 {
    classes
        .iter()
        .map(|cl| part(cl, geometry_pixels))
        .sum::<f64>()
        .sqrt()
}

/// What a step changes: a filter class to its plan, more samples, or a finer map.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Rung {
    Plan,
    Samples,
    Texels,
}

/// A class's step in a round: where its rungs lead, the last rung's kind, the bound the model
/// predicts there, and the predicted cost of rendering it.
#[derive(Clone, Copy, Debug)]
struct Step {
    class: usize,
    share: f64,
    at: Option<(u32, u32)>,
    kind: Rung,
    predicted: f64,
    paid: f64,
}

impl Class {
    /// Its best bound so far (1 where it has none).
    fn bound(&self) -> f64 {
        self.best.as_ref().map_or(1.0, |(_, c, _)| c.bound)
    }
}

/// A class's part of the frame's MSE bound: its pixels' share times its best bound squared (1
/// where it has none).
fn part(cl: &Class, geometry_pixels: usize) -> f64 {
    cl.design.pixel_count() as f64 / geometry_pixels as f64 * cl.bound().powi(2)
}

/// Which classes keep the filter: all that have its bound, then, while the frame's predicted MSE
/// (a filter class at its bound, a planned class at T) is over T², the filter class over T whose
/// move to the plan removes the most predicted MSE per unit of the plan's cost.
fn filter_split(classes: &mut [Class], geometry_pixels: usize, target: f64) {
    let t2 = target * target;
    let share = |cl: &Class| cl.design.pixel_count() as f64 / geometry_pixels as f64;
    let on_filter = |cl: &Class| matches!(cl.best.as_ref(), Some((Setting::Filter, _, _)));
    let predicted = |classes: &[Class]| -> f64 {
        classes
            .iter()
            .map(|cl| match &cl.best {
                Some((Setting::Filter, c, _)) if cl.setting == Setting::Filter => {
                    share(cl) * c.bound * c.bound
                }
                _ => share(cl) * t2,
            })
            .sum()
    };
    for cl in classes.iter_mut() {
        cl.setting = if on_filter(cl) {
            Setting::Filter
        } else {
            cl.plan
        };
    }
    while predicted(classes) > t2 {
        let worst = classes
            .iter_mut()
            .filter(|cl| cl.setting == Setting::Filter)
            .filter_map(|cl| {
                let b = cl.best.as_ref().map(|(_, c, _)| c.bound)?;
                let gain = share(cl) * (b * b - t2);
                (gain > 0.0).then_some((gain / cl.plan_cost.max(1.0), cl))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0));
        match worst {
            Some((_, cl)) => cl.setting = cl.plan,
            None => break,
        }
    }
}

/// The next side up by half an octave (a multiple of 16), at most `max`.
fn half_octave_up(size: u32, max: u32) -> u32 {
    super::half_octave(size as f32 * std::f32::consts::SQRT_2 * 1.001)
        .max(size + 16)
        .min(max)
}

impl State {
    /// The certified frame: the filter, the exact pixels, the plan or the frame-wide grid, the
    /// step-ups, and V written as the classes' settings give it. Returns maps rendered and syncs.
    pub(super) fn certified_frame(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        words: &[u32],
        class_groups: Vec<Group>,
        record: &mut serde_json::Value,
    ) -> Result<(u32, u32)> {
        let start = std::time::Instant::now();
        let ctx = fg.ctx;
        let target = self.method.target as f64;
        if self.certifying.is_none() {
            let filter = if self.method.filter {
                let pcss = Method::parse("pcss", &[])?;
                pcss.check_light(fg.scene)
                    .is_ok()
                    .then(|| Candidates::new(vec![pcss], Vec::new()))
            } else {
                None
            };
            self.certifying = Some(Certifying {
                tracer: TruthTracer::new(ctx, fg.scene)?,
                filter,
            });
        }
        let (mut maps, mut syncs) = (0u32, 0u32);
        let (w, h) = (fg.gbuffer.width, fg.gbuffer.height);
        let g = timer.cpu(Stage::READBACK, || {
            crate::render::gbuffer::read_back(ctx, &fg.gbuffer)
        })?;
        let geometry: Vec<bool> = (0..g.position.len()).map(|i| g.is_geometry(i)).collect();
        let geometry_pixels = geometry.iter().filter(|&&b| b).count().max(1);
        let lists = self.class_tiles(fg, timer)?;
        syncs += 2;
        // 1. The filter over the whole frame: its V, the designs' proxy and a candidate per class.
        let v_filter = match self.certifying.as_mut().and_then(|m| m.filter.as_mut()) {
            Some(f) => {
                fg.clear_visibility();
                let m = f.run(0, fg, timer)?.shadow_maps;
                // The filter's map is rendered every frame (it keeps none).
                self.reuse.add(&ReuseCounts::all_rendered(
                    m,
                    fg.scene.render.shadow_map_size,
                ));
                maps += m;
                syncs += 1;
                Some(read_v(fg, timer)?)
            }
            None => None,
        };
        // 2. The designs and the exact pixels, one trace for every class.
        let count = class_groups.len().max(1);
        let delta = self.method.delta as f64 / count as f64;
        let k = self.method.pixels as usize;
        let mut classes: Vec<Class> = Vec::new();
        for group in &class_groups {
            let c = group.classes[0];
            let mut mask = vec![false; geometry.len()];
            for &tile in &lists[c] {
                let tiles_x = w.div_ceil(TILE);
                let (x0, y0) = ((tile % tiles_x) * TILE, (tile / tiles_x) * TILE);
                for y in y0..(y0 + TILE).min(h) {
                    for x in x0..(x0 + TILE).min(w) {
                        let p = (y * w + x) as usize;
                        mask[p] = geometry[p];
                    }
                }
            }
            if !mask.iter().any(|&b| b) {
                continue;
            }
            let proxy = match &v_filter {
                Some(v) => design::band(v, &mask, w, h, design::BAND_DILATE),
                None => vec![0.0; mask.len()],
            };
            let design = Design::new(&mask, &proxy, design::DEFENSIVE)?;
            let kind = certify::kind_for_target(target, k, delta, design.max_weight());
            let own = self.sized(
                fg,
                Group {
                    n: group.n,
                    classes: vec![c],
                    tiles: group.tiles,
                    texel_need: group.texel_need,
                    window: group.window,
                    size: 0,
                    extent: 0.0,
                },
            );
            let plan = Setting::Grid {
                n: group.n,
                size: group.size,
            };
            classes.push(Class {
                class: c,
                mask,
                design,
                sampled: None,
                kind,
                setting: plan,
                plan,
                own,
                plan_cost: self.cost(group),
                best: None,
                tried: Vec::new(),
                steps: 0,
                current: 1.0,
                exhausted: false,
                texels: false,
            });
        }
        let seed = certify::Options::default().seed;
        let draws: Vec<_> = classes
            .iter()
            .map(|cl| cl.design.draw(k, seed ^ (cl.class as u64 + 1)))
            .collect();
        let mut unique: Vec<u32> = draws.iter().flat_map(|d| d.unique()).collect();
        unique.sort_unstable();
        unique.dedup();
        let tracer = &self.certifying.as_ref().expect("built above").tracer;
        let points: Vec<_> = unique.iter().map(|&p| truth::point_of(&g, p)).collect();
        let counts = timer.cpu(Stage::TRUTH_TRACE, || {
            tracer.trace(ctx, &truth::REFERENCE_SAMPLES, &points, &|_| {})
        })?;
        syncs += 1;
        let mut values = vec![0.0f32; geometry.len()];
        for (i, &p) in unique.iter().enumerate() {
            values[p as usize] = counts.visibility(i);
        }
        for (cl, draw) in classes.iter_mut().zip(draws) {
            cl.sampled = Some(Sampled::from_values(draw, &values));
        }
        let test = |cl: &mut Class, setting: Setting, v: &[f32]| {
            let cert = certify::certificate(
                v,
                cl.sampled.as_ref().expect("traced"),
                &cl.design,
                delta,
                cl.kind,
            );
            cl.tried.push((label(setting), cert.bound));
            cl.current = cert.bound;
            let better = cl
                .best
                .as_ref()
                .is_none_or(|(_, b, _)| cert.bound < b.bound);
            if better {
                let pixels = v
                    .iter()
                    .zip(&cl.mask)
                    .map(|(&x, &m)| if m { x } else { 0.0 })
                    .collect();
                cl.best = Some((setting, cert, pixels));
            }
        };
        // 3. The filter where the frame's budget lets it stay: every class bounded on its V, the
        // split keeps it where the others leave room (where it fits every class, it is the frame).
        if let Some(v) = &v_filter {
            for cl in classes.iter_mut() {
                test(cl, Setting::Filter, v);
            }
        }
        filter_split(&mut classes, geometry_pixels, target);
        let all_filter = !classes.is_empty()
            && classes.iter().all(|cl| cl.setting == Setting::Filter)
            && frame_bound(&classes, geometry_pixels) <= target;
        // 4. The grids' plan against the frame-wide grid.
        let planned: Vec<Group> = class_groups
            .iter()
            .filter(|g| {
                !classes
                    .iter()
                    .any(|cl| cl.class == g.classes[0] && cl.setting == Setting::Filter)
            })
            .map(|g| Group {
                n: g.n,
                classes: g.classes.clone(),
                tiles: g.tiles,
                texel_need: g.texel_need,
                window: g.window,
                size: g.size,
                extent: g.extent,
            })
            .collect();
        let mut groups = if self.method.merge {
            self.merged(fg, planned)
        } else {
            planned
        };
        let plan_cost: f64 = groups.iter().map(|g| self.cost(g)).sum();
        let frame_wide = self.frame_wide(fg, &class_groups);
        let frame_cost = frame_wide.as_ref().map_or(f64::INFINITY, |g| self.cost(g));
        let fallback = if all_filter {
            Some("pcss".to_string())
        } else {
            match (self.method.fallback, frame_wide) {
                (Some(ratio), Some(fw)) if frame_cost <= ratio as f64 * plan_cost => {
                    let name = format!("regular:n={},layout=centred @ {}", fw.n, fw.size);
                    for cl in classes.iter_mut() {
                        // Frame-wide: every class is shaded by the grid, whatever the filter did.
                        cl.best = None;
                        cl.setting = Setting::Grid {
                            n: fw.n,
                            size: fw.size,
                        };
                    }
                    groups = vec![fw];
                    Some(name)
                }
                _ => None,
            }
        };
        // 5. The grids rendered and measured.
        let mut v = v_filter.clone().unwrap_or_default();
        if !all_filter && !groups.is_empty() {
            self.hold_windows(fg, &mut groups);
            fg.clear_visibility();
            let (m, s) = self.render_groups(fg, timer, &groups, words, record)?;
            maps += m;
            syncs += s + 1;
            v = read_v(fg, timer)?;
            for group in &groups {
                for cl in classes
                    .iter_mut()
                    .filter(|cl| group.classes.contains(&cl.class))
                {
                    if cl.setting == Setting::Filter && fallback.is_none() {
                        continue;
                    }
                    cl.setting = Setting::Grid {
                        n: group.n,
                        size: group.size,
                    };
                    let s = cl.setting;
                    test(cl, s, &v);
                }
            }
        } else {
            record["classes"] = serde_json::json!(Vec::<ClassRecord>::new());
            self.classes.clear();
        }
        // 6. While the frame's bound is over T, the classes over T holding most of the excess step
        // up, alone on their own windows, in one render between clears (`step_round`).
        loop {
            if frame_bound(&classes, geometry_pixels) <= target {
                break;
            }
            let round: Vec<(Step, Group, f64)> = self
                .step_round(&mut classes, geometry_pixels)
                .into_iter()
                .filter_map(|st| {
                    let (n2, size2) = st.at?;
                    let cl = &mut classes[st.class];
                    let before = cl.current;
                    cl.setting = Setting::Grid { n: n2, size: size2 };
                    cl.steps += 1;
                    let mut group = Group {
                        n: n2,
                        classes: vec![cl.class],
                        tiles: cl.own.tiles,
                        texel_need: cl.own.texel_need,
                        window: cl.own.window,
                        size: 0,
                        extent: 0.0,
                    };
                    group.extent = super::window_extent(fg, &group.window);
                    group.size = size2;
                    Some((st, group, before))
                })
                .collect();
            if round.is_empty() {
                break;
            }
            fg.clear_visibility();
            for (k, (_, group, _)) in round.iter().enumerate() {
                let out = self.render_group(fg, timer, k, group, words)?;
                maps += out.shadow_maps;
                syncs += out.syncs;
                for r in self
                    .classes
                    .iter_mut()
                    .filter(|r| r.class as usize == group.classes[0])
                {
                    r.n = group.n;
                    r.map_size = group.size;
                    r.maps = out.shadow_maps;
                    r.extent = group.extent;
                }
            }
            let stepped = read_v(fg, timer)?;
            syncs += 1;
            for (st, group, before) in &round {
                let s = Setting::Grid {
                    n: group.n,
                    size: group.size,
                };
                let cl = &mut classes[st.class];
                test(cl, s, &stepped);
                // A rung that bought under a quarter of the drop its model predicted: samples
                // turn to texels, texels end the class (a filter class's plan is not a rung).
                let (want, got) = (before - st.predicted, before - cl.current);
                if st.kind != Rung::Plan && want > 0.0 && got < 0.25 * want {
                    if st.kind == Rung::Samples {
                        cl.texels = true;
                    } else {
                        cl.exhausted = true;
                    }
                }
            }
        }
        // 7. V: each class's best setting's pixels (the certified one where there is one).
        if v.is_empty() {
            v = vec![0.0; geometry.len()];
        }
        let mut frame_mse = 0.0f64;
        let mut measures = Vec::new();
        for cl in &classes {
            let (setting, cert, pixels) = cl.best.as_ref().expect("measured once at least");
            for (p, &m) in cl.mask.iter().enumerate() {
                if m {
                    v[p] = pixels[p];
                }
            }
            let n_c = cl.design.pixel_count();
            let share = n_c as f64 / geometry_pixels as f64;
            frame_mse += share * cert.bound * cert.bound;
            measures.push(ClassMeasure {
                class: cl.class as u32,
                setting: label(*setting),
                steps: cl.steps,
                bound: cert.bound,
                sampled_rmse: cert.sampled_rmse,
                certified: cert.bound <= target,
                tried: cl.tried.clone(),
                pixels: n_c,
                share,
            });
            if *setting == Setting::Filter {
                for r in self
                    .classes
                    .iter_mut()
                    .filter(|r| r.class as usize == cl.class)
                {
                    r.n = 0;
                }
            }
        }
        ctx.queue
            .write_buffer(&fg.visibility, 0, bytemuck::cast_slice(&v));
        let bound = frame_mse.sqrt();
        let met = bound <= target;
        record["classes"] = serde_json::json!(self.classes);
        record["target"] = target.into();
        record["target_met"] = met.into();
        record["certified"] = serde_json::json!({
            "decision_ms": start.elapsed().as_secs_f64() * 1e3,
            "bound": bound,
            "delta": self.method.delta,
            "pixels_per_class": k,
            "traced_pixels": unique.len(),
            "trace_ms": counts.ms,
            "rays": counts.rays(),
            "classes": measures,
            "fallback": {
                "taken": fallback.is_some(),
                "setting": fallback,
                "plan_cost": plan_cost,
                "frame_wide_cost": frame_cost,
                "ratio": self.method.fallback,
            },
            "clock": "wall clock, ms: decision_ms from the filter to V written (the grids' renders and step-ups included); trace_ms the exact pixels' trace (stages_ms.truth_trace)",
        });
        Ok((maps, syncs))
    }

    /// The frame-wide grid: every class's tiles, the top class's samples, the union of the
    /// windows and the finest texel need.
    fn frame_wide(&self, fg: &FrameGpu, class_groups: &[Group]) -> Option<Group> {
        let first = class_groups.first()?;
        let mut all = Group {
            n: first.n,
            classes: Vec::new(),
            tiles: 0,
            texel_need: f32::INFINITY,
            window: first.window,
            size: 0,
            extent: 0.0,
        };
        for g in class_groups {
            all.n = all.n.max(g.n);
            all.classes.extend(&g.classes);
            all.tiles += g.tiles;
            all.texel_need = all.texel_need.min(g.texel_need);
            all.window = crate::scene::light::Bounds {
                min: all.window.min.min(g.window.min),
                max: all.window.max.max(g.window.max),
            };
        }
        Some(self.sized(fg, all))
    }

    /// The classes to step up in one round, with their next (n, size). Among the classes whose
    /// bound is over T, rung by rung, the step that removes the most predicted MSE from the frame
    /// per unit of predicted cost (`State::cost`: a class's first step in a round pays its whole
    /// render, a further rung only the difference), until the step model predicts the frame
    /// within T²: a sample rung scales the bound by (n/n')^1.5, a finer map (past `max_n`) by
    /// 1/√2, a filter class's plan meets T. So the steps go where they are cheapest for the
    /// frame, and one class stepped far can carry it. A class at its ladder's end is marked.
    fn step_round(&self, classes: &mut [Class], geometry_pixels: usize) -> Vec<Step> {
        let target = self.method.target as f64;
        let t2 = target * target;
        let mut planned: Vec<Step> = classes
            .iter()
            .enumerate()
            .filter(|(_, cl)| !cl.exhausted && cl.bound() > target)
            .map(|(i, cl)| Step {
                class: i,
                share: cl.design.pixel_count() as f64 / geometry_pixels as f64,
                at: None,
                kind: Rung::Plan,
                predicted: cl.current,
                paid: 0.0,
            })
            .collect();
        // A class's part of the frame's MSE: its best bound, or its step's predicted one if lower.
        let part_of = |st: &Step, cl: &Class| st.share * cl.bound().min(st.predicted).powi(2);
        let mut predicted: f64 = classes.iter().map(|cl| part(cl, geometry_pixels)).sum();
        while predicted > t2 {
            let mut best: Option<(f64, usize, Step, f64)> = None;
            for (k, st) in planned.iter().enumerate() {
                let cl = &classes[st.class];
                let next = match (st.at, cl.setting) {
                    (None, Setting::Filter) => match cl.plan {
                        Setting::Grid { n, size } => {
                            Some((n, size, Rung::Plan, target.min(st.predicted)))
                        }
                        Setting::Filter => None,
                    },
                    (Some((n, size)), _) | (None, Setting::Grid { n, size }) => self
                        .next_rung(n, size, cl.texels)
                        .map(|(n2, size2, kind, scale)| (n2, size2, kind, st.predicted * scale)),
                };
                let Some((n2, size2, kind, b2)) = next else {
                    continue;
                };
                let cost = self.cost(&Group {
                    n: n2,
                    size: size2,
                    classes: Vec::new(),
                    tiles: cl.own.tiles,
                    texel_need: cl.own.texel_need,
                    window: cl.own.window,
                    extent: 0.0,
                });
                let stepped = Step {
                    at: Some((n2, size2)),
                    kind,
                    predicted: b2,
                    paid: cost,
                    ..*st
                };
                let gain = part_of(st, cl) - part_of(&stepped, cl);
                let worth = gain / (cost - st.paid).max(1.0);
                if gain > 0.0 && best.as_ref().is_none_or(|w| worth > w.0) {
                    best = Some((worth, k, stepped, gain));
                }
            }
            let Some((_, k, stepped, gain)) = best else {
                break;
            };
            predicted -= gain;
            planned[k] = stepped;
        }
        for st in &planned {
            let cl = &mut classes[st.class];
            let at_end = match cl.setting {
                Setting::Grid { n, size } => self.next_rung(n, size, cl.texels).is_none(),
                Setting::Filter => false,
            };
            if st.at.is_none() && at_end {
                cl.exhausted = true;
            }
        }
        planned.retain(|st| st.at.is_some());
        planned
    }

    /// The rung after (n, size) with its model's scale of the bound: the next samples per side
    /// of the ladder (sampling error falls about as n^-1.5), past `max_n` or for a class whose
    /// samples stopped paying (`texels`) the map half an octave finer (at most `max_size`);
    /// None at the ladder's end. The plan's sides are ample where it under-counts
    /// (docs/regions.md, "Texels"), and a finer side costs every map, so the samples come first.
    fn next_rung(&self, n: u32, size: u32, texels: bool) -> Option<(u32, u32, Rung, f64)> {
        let (max_n, max_size) = (self.method.max_n, self.method.max_size);
        let rung = LADDER.iter().copied().find(|&r| r > n && r <= max_n);
        if let (Some(n2), false) = (rung, texels) {
            return Some((n2, size, Rung::Samples, (n as f64 / n2 as f64).powf(1.5)));
        }
        let size2 = half_octave_up(size, max_size);
        (size2 > size).then_some((n, size2, Rung::Texels, std::f64::consts::FRAC_1_SQRT_2))
    }

    /// Each class's tiles (tile = x + y · tiles across), read back from the decision.
    fn class_tiles(&self, fg: &FrameGpu, timer: &mut StageTimer) -> Result<Vec<Vec<u32>>> {
        let p = &self.pass;
        let section = p.params.section_words as usize;
        let classes = p.params.ladder_len as usize;
        let words: Vec<u32> = timer.cpu(Stage::READBACK, || {
            readback::read_buffer(fg.ctx, &p.class_tiles, (classes * section) as u64 * 4)
        })?;
        Ok((0..classes)
            .map(|c| {
                let base = c * section;
                let count = words[base] as usize;
                let start = base + TILE_LIST_HEADER;
                words[start..start + count].to_vec()
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::light::Bounds;

    /// A class of `pixels` geometry pixels (of a 100-pixel frame) whose filter's bound is `filter`.
    fn class(c: usize, pixels: usize, filter: f64, plan_cost: f64) -> Class {
        let mask: Vec<bool> = (0..100).map(|p| p < pixels).collect();
        let design = Design::new(&mask, &vec![0.0; 100], design::DEFENSIVE).unwrap();
        let cert = Certificate {
            pixels: 1,
            unique_pixels: 1,
            delta: 0.05,
            sampled_rmse: filter,
            bound: filter,
            bound_kind: BoundKind::PerFrame,
            per_frame_bound: filter,
            calibrated_bound: filter,
            student_t_bound: filter,
            stretch: 1.0,
            subset_pixels: pixels,
            defensive: 0.0,
            max_weight: 1.0,
        };
        let plan = Setting::Grid { n: 4, size: 512 };
        Class {
            class: c,
            mask,
            design,
            sampled: None,
            kind: BoundKind::PerFrame,
            setting: plan,
            plan,
            own: Group {
                n: 4,
                classes: vec![c],
                tiles: 1,
                texel_need: 1.0,
                window: Bounds {
                    min: glam::Vec3::ZERO,
                    max: glam::Vec3::ONE,
                },
                size: 512,
                extent: 1.0,
            },
            plan_cost,
            best: Some((Setting::Filter, cert, Vec::new())),
            tried: vec![("pcss".into(), filter)],
            steps: 0,
            current: filter,
            exhausted: false,
            texels: false,
        }
    }

    #[test]
    fn the_filter_stays_over_t_where_the_others_leave_room() {
        // T = 0.03, T² = 9e-4. All on the filter: 0.5·1e-6 + 0.1·1.6e-3 + 0.4·6.4e-3 = 2.7205e-3.
        // Moving the third class to its plan (predicted at T) removes 0.4·(6.4e-3 − 9e-4) = 2.2e-3,
        // the second only 0.1·(1.6e-3 − 9e-4) = 7e-5 (at equal cost): the third moves, and the
        // frame's prediction 0.5e-6 + 1.6e-4 + 3.6e-4 = 5.205e-4 is within T², so the second
        // keeps the filter with its bound 0.04 over T.
        let mut classes = vec![
            class(0, 50, 0.001, 1e6),
            class(1, 10, 0.04, 1e6),
            class(2, 40, 0.08, 1e6),
        ];
        // Each class's pixels are the first N of the frame: shares from disjoint counts.
        filter_split(&mut classes, 100, 0.03);
        let settings: Vec<Setting> = classes.iter().map(|c| c.setting).collect();
        assert_eq!(
            settings,
            [
                Setting::Filter,
                Setting::Filter,
                Setting::Grid { n: 4, size: 512 }
            ]
        );
        // The price decides between equal gains: with the third class's plan 100 times dearer,
        // the second's cheaper move comes first, and the third must still follow (2.65e-3 > T²).
        let mut classes = vec![
            class(0, 50, 0.001, 1e6),
            class(1, 10, 0.04, 1e6),
            class(2, 40, 0.08, 1e8),
        ];
        filter_split(&mut classes, 100, 0.03);
        assert!(classes[1..]
            .iter()
            .all(|c| c.setting == Setting::Grid { n: 4, size: 512 }));
        // At a loose target every class keeps the filter.
        let mut classes = vec![class(0, 50, 0.001, 1e6), class(1, 50, 0.08, 1e6)];
        filter_split(&mut classes, 100, 0.2);
        assert!(classes.iter().all(|c| c.setting == Setting::Filter));
    }
}
