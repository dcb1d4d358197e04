//! auto's certified decision (docs/certify.md §5). The estimate's search gives the first guess G:
//! its grid, its V and its per-pixel bound, the truth-free proxy the exact pixels are drawn by.
//! One set of K exact pixels then serves every candidate, tested cheapest first by the price, and
//! the first whose bound on its RMSE is at most the target is what the frame renders: first the
//! candidates cheaper than G (the one-map filters, and the grids the estimate does not put over
//! `SKIP` times the target), at most `MAX_BELOW` of them; then G and the dearer grids, at most
//! `MAX_ABOVE`. The order is fixed by the prices and the estimate, never by the exact pixels.
//! Where none is certified, the target is out of reach: the candidate with the least bound is
//! rendered, and says so.

use super::filter::{bound as filter_bound, read_v};
use super::record::{AutoRecord, Certified, Chosen};
use super::{sides, sizes, AutoState, Search, Try, KEEP};
use crate::certify::design::{self, Design};
use crate::certify::truth::TruthTracer;
use crate::certify::{self, certificate, Options};
use crate::gpu::timing::StageTimer;
use crate::methods::MethodOutput;
use crate::stages::FrameGpu;
use crate::Result;
use std::time::Instant;

/// A grid cheaper than the first guess that the estimate predicts over this many times the
/// target is not tried: the calibrated estimate reads 0.74–2.3 times the measure on scenes it was
/// not fitted on (measured/calibrated 0.43–1.36, docs/budget.md §8).
const SKIP: f64 = 1.6;
/// Grids tested at most below the first guess (the nearest it in price; the filters besides), and
/// candidates from it up.
const MAX_BELOW: usize = 5;
const MAX_ABOVE: usize = 5;

/// What `pixels` > 0 adds to auto: the truth tracer and the options.
pub(super) struct Certifying {
    tracer: TruthTracer,
    options: Options,
}

impl Certifying {
    pub(super) fn new(fg: &FrameGpu, pixels: usize, delta: f64) -> Result<Certifying> {
        Ok(Certifying {
            tracer: TruthTracer::new(fg.ctx, fg.scene)?,
            options: Options {
                pixels,
                delta,
                ..Default::default()
            },
        })
    }
}

/// A candidate: a centred grid (n, map size) or one-map filter `i`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Candidate {
    Grid(u32, u32),
    Filter(usize),
}

/// One candidate's test, as the record keeps it.
#[derive(Clone, Debug, serde::Serialize)]
struct Test {
    candidate: String,
    price: f64,
    maps: u32,
    bound: f64,
    sampled_rmse: f64,
    certified: bool,
}

/// A tested candidate's V and per-pixel bound (the error-bound picture).
struct Tested {
    candidate: Candidate,
    v: Vec<f32>,
    pixel_bound: Vec<f32>,
    bound: f64,
}

impl AutoState {
    /// The frame's decision by the bound, its record and its output. V holds the first guess's.
    pub(super) fn certified_frame(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        geometry: &[bool],
        search: Search,
    ) -> Result<MethodOutput> {
        let Search {
            tries,
            bound: first_bound,
            settles,
            ..
        } = search;
        let start = Instant::now();
        let target = self.method.target as f64;
        let first = *tries.last().expect("one try at least");
        // A sequence's handed-on choice is kept within KEEP of the target, and only rises.
        let handed = self.recalled && tries.len() == 1;
        let v_first = read_v(fg, timer)?;
        let g = timer.cpu(crate::gpu::Stage::READBACK, || {
            crate::render::gbuffer::read_back(fg.ctx, &fg.gbuffer)
        })?;
        let band = design::band(&v_first, geometry, g.width, g.height, design::BAND_DILATE);
        let design = Design::new(
            geometry,
            &design::proxy(&[&band, &first_bound], geometry),
            design::DEFENSIVE,
        )?;
        let c = self
            .certifying
            .as_ref()
            .expect("certified_frame runs with pixels > 0");
        let options = c.options;
        let sampled = certify::sample(fg.ctx, &c.tracer, &g, &design, &options)?;
        let kind =
            certify::kind_for_target(target, options.pixels, options.delta, design.max_weight());
        let order = self.order(&first, target, handed, fg.scene.render.shadow_map_size);
        let (mut tests, mut tested, mut maps) = (Vec::new(), Vec::<Tested>::new(), 0u32);
        let mut chosen = None;
        for (k, (candidate, price)) in order.iter().enumerate() {
            let (v, pixel_bound, m) = match *candidate {
                Candidate::Grid(n, size) if (n, size) == (first.n, first.map_size) => {
                    (v_first.clone(), first_bound.clone(), 0)
                }
                Candidate::Grid(n, size) => {
                    let (t, b) = self.try_grid(fg, timer, geometry, (n, size))?;
                    (read_v(fg, timer)?, b, t.maps)
                }
                Candidate::Filter(i) => {
                    timer.flush(fg.ctx);
                    fg.clear_visibility();
                    let m = self.filters.run(i, fg, timer)?.shadow_maps;
                    let v = read_v(fg, timer)?;
                    let b = filter_bound(&v, &v_first, &first_bound);
                    (v, b, m)
                }
            };
            maps += m;
            let cert = certificate(&v, &sampled, &design, options.delta, kind);
            let limit = if handed && k == 0 {
                target * KEEP
            } else {
                target
            };
            let certified = cert.bound <= limit;
            tests.push(Test {
                candidate: self.candidate_label(*candidate),
                price: *price,
                maps: m,
                bound: cert.bound,
                sampled_rmse: cert.sampled_rmse,
                certified,
            });
            tested.push(Tested {
                candidate: *candidate,
                v,
                pixel_bound,
                bound: cert.bound,
            });
            if certified {
                chosen = Some(tested.len() - 1);
                break;
            }
        }
        // Out of reach: the least bound tested, which says so.
        let met = chosen.is_some();
        let pick = chosen.unwrap_or_else(|| {
            (0..tested.len())
                .min_by(|&a, &b| tested[a].bound.total_cmp(&tested[b].bound))
                .expect("one test at least")
        });
        let Tested {
            candidate,
            v,
            pixel_bound,
            bound,
        } = tested.swap_remove(pick);
        fg.ctx
            .queue
            .write_buffer(&fg.visibility, 0, bytemuck::cast_slice(&v));
        self.filter = None;
        match candidate {
            Candidate::Grid(n, size) => {
                self.choice = (n, size);
                // The settled frames render the chosen grid: hold it (its V is written above).
                self.hold(fg, (n, size))?;
            }
            Candidate::Filter(i) => self.filter = Some(i),
        }
        let kept = handed && met && tests.len() == 1 && bound > target;
        let decision_ms = start.elapsed().as_secs_f64() * 1e3;
        let trace = sampled.trace.expect("traced");
        // Out of reach: the record says so in `warning`; the state's first such frame also hands
        // the line to the program (the binary prints it).
        let warning = (!met).then(|| {
            format!(
                "auto: target RMSE {} is out of reach within n ≤ {} and {}² maps: the least certified bound is {bound:.5} ({}, {} of {} candidates tested)",
                self.method.target,
                self.method.max_n,
                self.method.max_size,
                self.candidate_label(candidate),
                tests.len(),
                order.len()
            )
        });
        if let Some(line) = warning.as_deref().filter(|_| !self.warned) {
            self.warned = true;
            crate::progress::notice(line);
        }
        let tries_maps: u32 = tries.iter().map(|t| t.maps).sum();
        let detail = serde_json::json!({
            "pixels": options.pixels,
            "unique_pixels": sampled.unique.len(),
            "delta": options.delta,
            "defensive": design.defensive,
            "max_weight": design.max_weight(),
            "candidates": order.len(),
            "trace": trace,
            "clock": "wall clock: the exact pixels and every candidate's render, ms",
        });
        let record = AutoRecord {
            method: super::record::TAG.into(),
            chosen: Chosen::centred(self.choice),
            target: self.method.target,
            // Met where the chosen candidate's bound is at most T; a handed-on choice kept within
            // KEEP of it is `kept`, not met.
            target_met: met && !kept,
            predicted_rmse: first.prediction.predicted_rmse,
            predicted_sampling: first.prediction.predicted_sampling,
            predicted_map: first.prediction.predicted_map,
            tries,
            certified: Some(Certified {
                bound,
                bound_kind: kind,
                decision_ms,
                tests: tests
                    .iter()
                    .map(serde_json::to_value)
                    .collect::<std::result::Result<_, _>>()
                    .map_err(|e| crate::Error::Limit(format!("auto: its record: {e}")))?,
                detail: serde_json::from_value(detail)
                    .map_err(|e| crate::Error::Limit(format!("auto: its record: {e}")))?,
            }),
            map_cost: self.map_cost(),
            filter: None,
            renders: self.filter.map(|i| self.filters.label(i)),
            maps_rendered: tries_maps + maps,
            estimated: true,
            kept,
            warning,
        };
        let syncs = 1 + record.tries.len() as u32 + tests.len() as u32;
        if settles || met {
            self.settled = Some((record.clone(), pixel_bound.clone()));
        }
        Ok(MethodOutput {
            shadow_maps: tries_maps + maps,
            syncs,
            record: record.to_value()?,
            pictures: Vec::new(),
            bound: Some(pixel_bound),
        })
    }

    /// The candidates in the order they are tested, with their prices: a handed-on choice first,
    /// then only dearer grids (a sequence's choice only rises); else those cheaper than the first
    /// guess (the filters, the grids the estimate does not put over SKIP × T), then the first
    /// guess and the dearer grids, each part cheapest first and cut at MAX_BELOW and MAX_ABOVE.
    fn order(
        &self,
        first: &Try,
        target: f64,
        handed: bool,
        scene_map_size: u32,
    ) -> Vec<(Candidate, f64)> {
        let (max_n, max_size) = (self.method.max_n, self.method.max_size);
        let grid_price = |n: u32, size: u32| (n * n) as f64 * self.ladder.costs.of(size);
        let here = grid_price(first.n, first.map_size);
        let mut order: Vec<(Candidate, f64)> = Vec::new();
        if !handed {
            // A one-map filter: its map and its filtering, priced as two maps of the scene's size.
            let scene_size = self
                .ladder
                .costs
                .0
                .iter()
                .map(|(z, _)| *z)
                .find(|&z| z >= scene_map_size)
                .or(self.ladder.costs.0.last().map(|(z, _)| *z))
                .unwrap_or(512);
            let filter_price = 2.0 * self.ladder.costs.of(scene_size);
            order.extend((0..self.filters.len()).map(|i| (Candidate::Filter(i), filter_price)));
        }
        for size in sizes(max_size) {
            for n in sides(max_n) {
                let price = grid_price(n, size);
                let predicted = super::predicted_at(self.ladder.class, &first.at(), (n, size));
                if price >= here || predicted <= SKIP * target {
                    order.push((Candidate::Grid(n, size), price));
                }
            }
        }
        order.sort_by(|a, b| a.1.total_cmp(&b.1));
        let is_first = |c: &(Candidate, f64)| c.0 == Candidate::Grid(first.n, first.map_size);
        let cut = order.iter().position(is_first).unwrap_or(order.len());
        let (below, above) = order.split_at(cut);
        // Below the first guess: every filter, and the grids nearest it in price.
        let grids_below: Vec<usize> = (0..below.len())
            .filter(|&i| matches!(below[i].0, Candidate::Grid(..)))
            .collect();
        let skip = grids_below.len().saturating_sub(MAX_BELOW);
        let kept_below = below
            .iter()
            .enumerate()
            .filter(|(i, c)| {
                matches!(c.0, Candidate::Filter(_)) || !grids_below[..skip].contains(i)
            })
            .map(|(_, c)| *c);
        let mut order: Vec<(Candidate, f64)> = kept_below
            .chain(above.iter().take(MAX_ABOVE).copied())
            .collect();
        if handed {
            order.retain(|c| c.1 > here || is_first(c));
            // The handed-on choice first, whatever its price.
            let handed_choice =
                match self.handed_filter.as_deref().and_then(|name| {
                    (0..self.filters.len()).find(|&i| self.filters.name(i) == name)
                }) {
                    Some(i) => (Candidate::Filter(i), 0.0),
                    None => (Candidate::Grid(first.n, first.map_size), here),
                };
            order.retain(|c| c.0 != handed_choice.0);
            order.insert(0, handed_choice);
            order.truncate(1 + MAX_ABOVE);
        }
        order
    }

    fn candidate_label(&self, c: Candidate) -> String {
        match c {
            Candidate::Grid(n, size) => format!("regular:n={n},layout=centred @ {size}"),
            Candidate::Filter(i) => self.filters.label(i),
        }
    }
}
