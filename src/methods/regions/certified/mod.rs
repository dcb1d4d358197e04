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
//! With `hold = on` (the default), a frame starts each class from the setting the previous frame
//! ended on, measured on this frame's draws: it steps up from there only where the frame's bound
//! is over T, and a class goes down to the filter only where the frame's bound stays below
//! T / BAND (`methods::hold`), so a class's setting does not change with the plan's noise from
//! frame to frame (`held`).
//!
//! Each class's bound is over its own pixels at confidence 1 − δ/C (C classes), so by the union
//! bound the frame's MSE is at most Σ_c (N_c/N) b_c² with probability 1 − δ. A class chooses
//! its setting on the same draws that bound it, so each setting it could end on is bounded at
//! δ/(C·S), S the settings reachable (`Regions::reachable_settings`), and the union over them
//! keeps the chosen one's at 1 − δ/C. The frame is `met`
//! only where that bound is at most T. The truth's trace is timed as its own stage
//! (`truth_trace`) inside the frame: the measurement's cost is part of the frame's time.

mod held;
mod split;
mod steps;

use super::record::{CertifiedRecord, ClassMeasure, FallbackRecord, RegionsRecord};
use super::{Group, State};
use crate::certify::bound::BoundKind;
use crate::certify::design::{self, Design};
use crate::certify::truth::{self, TruthSamples, TruthTracer};
use crate::certify::{self, Certificate, Sampled};
use crate::gpu::timing::StageTimer;
use crate::gpu::{readback, Stage};
use crate::methods::auto::filter::{read_v, Candidates};
use crate::methods::Method;
use crate::render::kept_maps::ReuseCounts;
use crate::stages::shade::{TILE, TILE_LIST_HEADER};
use crate::stages::FrameGpu;
use crate::Result;
pub(super) use held::Settled;

/// What `certify = on` keeps from frame to frame: the truth tracer and the filter's state.
pub(super) struct Certifying {
    tracer: TruthTracer,
    filter: Option<Candidates>,
}

/// How a class is shaded in the end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Setting {
    /// A centred grid of n × n samples on maps of `size`, over the class's own window.
    Grid { n: u32, size: u32 },
    /// The one-map filter's V.
    Filter,
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

/// One certified frame as its parts share it: the classes with their draws and exact pixels,
/// the filter's V, and what the frame has paid so far.
struct Measure {
    classes: Vec<Class>,
    geometry_pixels: usize,
    /// V's length: every pixel of the screen.
    screen: usize,
    v_filter: Option<Vec<f32>>,
    delta: f64,
    traced: usize,
    trace_ms: f64,
    rays: u64,
    maps: u32,
    syncs: u32,
    /// The previous frame's windows (`State::held`), which this frame's step-ups keep.
    previous: Vec<(u32, u32, crate::scene::light::Bounds)>,
}

/// `v` bounded on the class's exact pixels, with `v`'s pixels within the class.
fn certified_on(cl: &Class, v: &[f32], delta: f64) -> (Certificate, Vec<f32>) {
    let cert = certify::certificate(
        v,
        cl.sampled.as_ref().expect("traced"),
        &cl.design,
        delta,
        cl.kind,
    );
    let pixels = v
        .iter()
        .zip(&cl.mask)
        .map(|(&x, &m)| if m { x } else { 0.0 })
        .collect();
    (cert, pixels)
}

/// `setting`'s V bounded on the class's exact pixels; the class keeps its best setting so far
/// (the lowest bound) with that V's pixels within it.
fn test(cl: &mut Class, setting: Setting, v: &[f32], delta: f64) {
    let (cert, pixels) = certified_on(cl, v, delta);
    cl.tried.push((label(setting), cert.bound));
    cl.current = cert.bound;
    if cl
        .best
        .as_ref()
        .is_none_or(|(_, b, _)| cert.bound < b.bound)
    {
        cl.best = Some((setting, cert, pixels));
    }
}

impl State {
    /// The certified frame: the filter, the exact pixels, the classes' settings (the previous
    /// frame's where they hold, else the filter's split, the plan or the frame-wide grid), the
    /// step-ups, and V written as the classes' settings give it. Returns maps rendered and syncs.
    pub(super) fn certified_frame(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        words: &[u32],
        class_groups: Vec<Group>,
        record: &mut RegionsRecord,
    ) -> Result<(u32, u32)> {
        let start = std::time::Instant::now();
        let mut m = self.measure(fg, timer, &class_groups)?;
        let settled = std::mem::take(&mut self.settled);
        let held = self.method.hold && !settled.is_empty();
        let (v, fallback) = if held {
            let v = self.held_choice(fg, timer, &mut m, &settled, words, record)?;
            // A held frame decides no fallback: its classes keep what they ended on.
            (v, FallbackRecord::held())
        } else {
            self.fresh_choice(fg, timer, &mut m, &class_groups, words, record)?
        };
        self.step_rounds(fg, timer, &mut m, words)?;
        let bound = self.finish(fg, &m, v, record);
        if self.method.hold {
            self.settled = Settled::after(&m.classes);
        }
        record.certified = Some(CertifiedRecord {
            decision_ms: start.elapsed().as_secs_f64() * 1e3,
            bound,
            delta: self.method.delta,
            delta_per_setting: m.delta,
            reachable_settings: self.method.reachable_settings(),
            pixels_per_class: self.method.pixels,
            traced_pixels: m.traced,
            trace_ms: m.trace_ms,
            rays: m.rays,
            classes: Self::measures(&m, self.method.target as f64),
            held,
            fallback,
            clock: "wall clock, ms: decision_ms from the filter to V written (the grids' renders and step-ups included); trace_ms the exact pixels' trace (stages_ms.truth_trace)",
        });
        Ok((m.maps, m.syncs))
    }

    /// The filter over the whole frame, the classes' designs from its V, and the exact pixels
    /// of every class's draws in one trace.
    fn measure(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        class_groups: &[Group],
    ) -> Result<Measure> {
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
        let (mut maps, mut syncs) = (0u32, 2u32);
        let (w, h) = (fg.gbuffer.width, fg.gbuffer.height);
        let g = timer.cpu(Stage::READBACK, || {
            crate::render::gbuffer::read_back(ctx, &fg.gbuffer)
        })?;
        let geometry: Vec<bool> = (0..g.position.len()).map(|i| g.is_geometry(i)).collect();
        let geometry_pixels = geometry.iter().filter(|&&b| b).count().max(1);
        let lists = self.class_tiles(fg, timer)?;
        // The filter's V: a candidate for every class, and the designs' proxy.
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
        // The union bound over the classes and over every setting a class could end on.
        let delta = self.method.delta as f64
            / (class_groups.len().max(1) * self.method.reachable_settings()) as f64;
        let k = self.method.pixels as usize;
        let mut classes: Vec<Class> = Vec::new();
        for group in class_groups {
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
        // The exact pixels: one trace for every class's draws.
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
        // The reference's 32 × 32 samples, or two independent estimates of fewer (`truth_side`).
        let samples: Vec<TruthSamples> = match self.method.truth_side {
            32 => vec![truth::REFERENCE_SAMPLES],
            m => truth::paired(m).to_vec(),
        };
        let (mut estimates, mut trace_ms, mut rays) = (Vec::new(), 0.0, 0u64);
        for s in &samples {
            let counts = timer.cpu(Stage::TRUTH_TRACE, || {
                tracer.trace(ctx, s, &points, &|_| {})
            })?;
            syncs += 1;
            let mut values = vec![0.0f32; geometry.len()];
            for (i, &p) in unique.iter().enumerate() {
                values[p as usize] = counts.visibility(i);
            }
            estimates.push(values);
            trace_ms += counts.ms;
            rays += counts.rays();
        }
        for (cl, draw) in classes.iter_mut().zip(draws) {
            cl.sampled = Some(match &estimates[..] {
                [one] => Sampled::from_values(draw, one),
                [first, second] => Sampled::from_pair(draw, first, second),
                _ => unreachable!("one or two estimates"),
            });
        }
        Ok(Measure {
            classes,
            geometry_pixels,
            screen: geometry.len(),
            v_filter,
            delta,
            traced: unique.len(),
            trace_ms,
            rays,
            maps,
            syncs,
            previous: self.held.clone(),
        })
    }

    /// Renders `groups` into V between clears and reads it back; the record gains the classes.
    fn render_read(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        m: &mut Measure,
        groups: &mut [Group],
        words: &[u32],
        record: &mut RegionsRecord,
    ) -> Result<Vec<f32>> {
        self.hold_windows(fg, groups);
        fg.clear_visibility();
        let (maps, syncs) = self.render_groups(fg, timer, groups, words, record)?;
        m.maps += maps;
        m.syncs += syncs + 1;
        read_v(fg, timer)
    }

    /// V from each class's best setting (the certified one where there is one), written to the
    /// frame; the record's target and classes. Returns the frame's bound.
    fn finish(
        &mut self,
        fg: &FrameGpu,
        m: &Measure,
        mut v: Vec<f32>,
        record: &mut RegionsRecord,
    ) -> f64 {
        if v.is_empty() {
            v = vec![0.0; m.screen];
        }
        for cl in &m.classes {
            let (setting, _, pixels) = cl.best.as_ref().expect("measured once at least");
            for (p, &inside) in cl.mask.iter().enumerate() {
                if inside {
                    v[p] = pixels[p];
                }
            }
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
        fg.ctx
            .queue
            .write_buffer(&fg.visibility, 0, bytemuck::cast_slice(&v));
        let target = self.method.target as f64;
        let bound = frame_bound(&m.classes, m.geometry_pixels);
        record.classes = self.classes.clone();
        record.target = Some(target);
        record.target_met = Some(bound <= target);
        bound
    }

    /// Each class's measurement as the record keeps it.
    fn measures(m: &Measure, target: f64) -> Vec<ClassMeasure> {
        m.classes
            .iter()
            .map(|cl| {
                let (setting, cert, _) = cl.best.as_ref().expect("measured once at least");
                let n_c = cl.design.pixel_count();
                ClassMeasure {
                    class: cl.class as u32,
                    setting: label(*setting),
                    steps: cl.steps,
                    bound: cert.bound,
                    sampled_rmse: cert.sampled_rmse,
                    certified: cert.bound <= target,
                    tried: cl.tried.clone(),
                    pixels: n_c,
                    share: n_c as f64 / m.geometry_pixels as f64,
                }
            })
            .collect()
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
