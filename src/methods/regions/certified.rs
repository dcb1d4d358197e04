//! `certify = on`: `regions` decides by measured error (docs/regions.md, "Certified classes").
//!
//! The plan (the classes' samples and map sides from the blocker search) is a guess that can
//! under-count a class's penumbra. So after the plan, each class's RMSE of V is bounded with the
//! exact truth at `pixels` pixels drawn within the class (its tiles' geometry pixels the design's
//! subset, `certify`), one trace for every class:
//! - a one-map filter (`pcss`, rendered once over the frame first) is kept for each class where
//!   its bound over the class is at most T; where it is for every class, the frame is the filter;
//! - the other classes' plan is priced against the frame-wide grid (the top class's samples on
//!   every tile, one window, `Group` cost); where the grid costs at most `fallback` times the
//!   plan, the frame takes the grid and says so;
//! - each class still over T is stepped up (more samples, a finer map, on its own window) and
//!   measured again with the same draws, until its bound is at most T or its ladder ends.
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
    /// The class alone: its own window and texel need (for steps).
    own: Group,
    best: Option<(Setting, Certificate, Vec<f32>)>,
    tried: Vec<(String, f64)>,
    steps: u32,
    done: bool,
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
        .map(|cl| {
            let b = cl.best.as_ref().map_or(1.0, |(_, c, _)| c.bound);
            cl.design.pixel_count() as f64 / geometry_pixels as f64 * b * b
        })
        .sum::<f64>()
        .sqrt()
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
            classes.push(Class {
                class: c,
                mask,
                design,
                sampled: None,
                kind,
                setting: Setting::Grid {
                    n: group.n,
                    size: group.size,
                },
                own,
                best: None,
                tried: Vec::new(),
                steps: 0,
                done: false,
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
        let test = |cl: &mut Class, setting: Setting, v: &[f32]| -> bool {
            let cert = certify::certificate(
                v,
                cl.sampled.as_ref().expect("traced"),
                &cl.design,
                delta,
                cl.kind,
            );
            cl.tried.push((label(setting), cert.bound));
            let better = cl
                .best
                .as_ref()
                .is_none_or(|(_, b, _)| cert.bound < b.bound);
            let certified = cert.bound <= target;
            if better {
                let pixels = v
                    .iter()
                    .zip(&cl.mask)
                    .map(|(&x, &m)| if m { x } else { 0.0 })
                    .collect();
                cl.best = Some((setting, cert, pixels));
            }
            if certified {
                cl.setting = setting;
                cl.done = true;
            }
            certified
        };
        // 3. The filter where it is certified within the class.
        if let Some(v) = &v_filter {
            for cl in classes.iter_mut() {
                test(cl, Setting::Filter, v);
            }
        }
        // The filter's frame: where its bound over the frame is at most T, it is the frame.
        let all_filter = v_filter.is_some() && frame_bound(&classes, geometry_pixels) <= target;
        if all_filter {
            for cl in classes.iter_mut() {
                cl.setting = Setting::Filter;
                cl.done = true;
            }
        }
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
                        cl.done = false;
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
                    if cl.done && fallback.is_none() {
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
        // 6. Each class still over T steps up, alone on its own window, all such classes in one
        // render between clears, until certified or at the ladder's end.
        loop {
            // The classes' shares of T² follow their pixels; a class under its share leaves the
            // rest to the others, so the steps stop once the frame's bound is at most T.
            if frame_bound(&classes, geometry_pixels) <= target {
                break;
            }
            let mut round: Vec<(usize, Group)> = Vec::new();
            for (i, cl) in classes.iter_mut().enumerate() {
                if cl.done {
                    continue;
                }
                let Setting::Grid { n, size } = cl.setting else {
                    cl.done = true;
                    continue;
                };
                let Some((n2, size2)) = self.step(n, size, cl) else {
                    cl.done = true;
                    continue;
                };
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
                round.push((i, group));
            }
            if round.is_empty() {
                break;
            }
            fg.clear_visibility();
            for (k, (_, group)) in round.iter().enumerate() {
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
            for (i, group) in &round {
                let s = Setting::Grid {
                    n: group.n,
                    size: group.size,
                };
                test(&mut classes[*i], s, &stepped);
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

    /// The next setting of a class over T, on its own window: the samples raised by the factor
    /// the bound asks for (sampling error falls about as n^-1.5; at least one rung of the ladder,
    /// at most `max_n`), else the map half an octave finer; None at the ladder's end.
    fn step(&self, n: u32, size: u32, cl: &Class) -> Option<(u32, u32)> {
        let (max_n, max_size) = (self.method.max_n, self.method.max_size);
        let over = cl
            .tried
            .last()
            .map_or(1.0, |(_, b)| (b / self.method.target as f64).max(1.0));
        let want = (n as f64 * over.powf(1.0 / 1.5)).ceil() as u32;
        let n2 = LADDER
            .iter()
            .copied()
            .find(|&r| r > n && r >= want)
            .unwrap_or(max_n)
            .min(max_n);
        // The maps only where the samples are at their most: the plan's sides are ample where
        // it under-counts (docs/regions.md, "Texels"), and a finer side costs every map.
        let size2 = if n2 > n {
            size
        } else {
            half_octave_up(size, max_size)
        };
        (n2 > n || size2 > size).then_some((n2.max(n), size2.max(size)))
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
