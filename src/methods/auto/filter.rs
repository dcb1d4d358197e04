//! auto's single-map check (docs/error-estimate.md §6): once a grid meets the target, each
//! candidate one-map method (`filters`, pcss by default) is screened against that grid, and those
//! left are set against the V of a finer grid, one predicted to err by half the target. The estimate has no reading of a filter's
//! own error, but that grid is a reference whose error it does know: the grid's and the filter's
//! errors come from unrelated causes (where the points fall, against one map's blocker estimate),
//! so with D the RMS over geometry pixels of their difference and σ the grid's predicted RMSE,
//! the filter's RMSE is predicted as sqrt(D² − σ²); per pixel, |V_f − V| ≤ |V_f − V_grid| +
//! |V_grid − V| bounds it by the difference plus the grid's bound. A filter predicted to meet the
//! target that took less time than the grid that met it is what the frame renders, and the
//! settled frames after it.

use crate::gpu::timing::StageTimer;
use crate::gpu::{readback, Stage};
use crate::methods::{Family, Method, MethodOutput, MethodState};
use crate::stages::FrameGpu;
use crate::{Error, Result};

/// `filters = none` or names joined by `+` (`pcss+msm`): one-map methods at their defaults.
pub(crate) fn parse_list(text: &str) -> Result<Vec<Method>> {
    if text == "none" {
        return Ok(Vec::new());
    }
    let mut out: Vec<Method> = Vec::new();
    for name in text.split('+') {
        let bad = |why: String| {
            Error::Param(format!("auto: filters = {text}: `{name}` {why}; give one-map methods joined by + (e.g. pcss+msm), or none"))
        };
        let m = Method::parse(name, &[]).map_err(|e| bad(format!("is not a method ({e})")))?;
        if !matches!(m.family(), Family::Pcf | Family::Filtered) || name.contains(':') {
            return Err(bad(
                "is not a filtered one-map method at its defaults".into()
            ));
        }
        if out.iter().any(|o| o.name() == m.name()) {
            return Err(bad("is given twice".into()));
        }
        out.push(m);
    }
    Ok(out)
}

/// The filter's predicted RMSE, sqrt(max(D² − σ², 0)), and D: the RMS over geometry pixels of
/// V_f − V_grid (both clamped to [0, 1], as the frame's V is), σ = `grid_rmse`.
pub(crate) fn predicted(
    v_filter: &[f32],
    v_grid: &[f32],
    geometry: &[bool],
    grid_rmse: f64,
) -> (f64, f64) {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for ((f, g), _) in v_filter
        .iter()
        .zip(v_grid)
        .zip(geometry)
        .filter(|(_, m)| **m)
    {
        let d = f64::from(f.clamp(0.0, 1.0)) - f64::from(g.clamp(0.0, 1.0));
        sum += d * d;
        n += 1;
    }
    let d = (sum / n.max(1) as f64).sqrt();
    ((d * d - grid_rmse * grid_rmse).max(0.0).sqrt(), d)
}

/// Per pixel: |V_f − V_grid| plus the grid's bound (0 off geometry, as the grid's is).
pub(crate) fn bound(v_filter: &[f32], v_grid: &[f32], grid_bound: &[f32]) -> Vec<f32> {
    v_filter
        .iter()
        .zip(v_grid)
        .zip(grid_bound)
        .map(|((f, g), b)| {
            if *b > 0.0 {
                (f.clamp(0.0, 1.0) - g.clamp(0.0, 1.0)).abs() + b
            } else {
                0.0
            }
        })
        .collect()
}

/// One candidate's check, as run.json's record keeps it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Check {
    pub method: String,
    pub maps: u32,
    /// Wall clock from its render to its V read back, ms (the grid's try: `tries[…].ms`).
    pub ms: f64,
    /// Its predicted RMSE against the grid that met the target (the screen).
    pub screened: f64,
    /// Against the reference: RMS of V_f − V_r over geometry pixels, and the predicted RMSE F.
    /// None where the screen or the time ruled it out, or no reference was rendered.
    pub difference: Option<f64>,
    pub predicted_rmse: Option<f64>,
    pub accepted: bool,
}

/// The grid that met the target, its V in the frame's V now: its predicted RMSE and the wall
/// clock of its try, which a filter must beat.
pub(crate) struct Met {
    pub(crate) rmse: f64,
    pub(crate) ms: f64,
}

/// The frame the candidates are read in: its GPU state and its geometry pixels.
pub(crate) struct Scope<'a> {
    pub(crate) fg: &'a FrameGpu<'a>,
    pub(crate) geometry: &'a [bool],
}

/// `check`'s rule: the grid that met the target, the screen a candidate must pass against it,
/// auto's acceptance `accept(F, handed)`, and the filter the previous frame of a sequence chose.
pub(crate) struct Against<'a> {
    pub(crate) met: Met,
    pub(crate) screen: f64,
    pub(crate) accept: &'a dyn Fn(f64, bool) -> bool,
    pub(crate) handed_on: Option<&'a str>,
}

/// `check_out_of_reach`'s rule: the grid the frame renders and its bound, the band `keep` a
/// handed-on filter is kept within, and that filter.
pub(crate) struct OutOfReach<'a> {
    pub(crate) met: Met,
    pub(crate) bound: &'a [f32],
    pub(crate) keep: f64,
    pub(crate) handed_on: Option<&'a str>,
}

/// The reference grid, rendered into V by auto when asked: its predicted RMSE, bound and maps,
/// and its try as the record keeps it.
pub(crate) struct Reference {
    pub(crate) rmse: f64,
    pub(crate) bound: Vec<f32>,
    pub(crate) maps: u32,
    pub(crate) record: super::Try,
}

/// The check's outcome: the chosen candidate with its prediction and bound.
pub(crate) struct Outcome {
    pub(crate) chosen: Option<(usize, f64, Vec<f32>)>,
    pub(crate) checks: Vec<Check>,
    pub(crate) maps: u32,
    pub(crate) reference: Option<super::Try>,
}

/// The candidates and their states (built on first use, then kept for the settled frames).
pub(crate) struct Candidates {
    methods: Vec<Method>,
    states: Vec<Option<Box<dyn MethodState>>>,
    /// Candidates of the default list that refuse the scene's light, by label.
    left_out: Vec<String>,
}

impl Candidates {
    pub(crate) fn new(methods: Vec<Method>, left_out: Vec<String>) -> Candidates {
        let states = methods.iter().map(|_| None).collect();
        Candidates {
            methods,
            states,
            left_out,
        }
    }
    pub(crate) fn left_out(&self) -> &[String] {
        &self.left_out
    }
    pub(crate) fn is_empty(&self) -> bool {
        self.methods.is_empty()
    }
    pub(crate) fn len(&self) -> usize {
        self.methods.len()
    }
    pub(crate) fn name(&self, i: usize) -> &'static str {
        self.methods[i].name()
    }
    pub(crate) fn label(&self, i: usize) -> String {
        self.methods[i].label()
    }

    /// Candidate `i` rendered into V (which the caller has cleared).
    pub(crate) fn run(
        &mut self,
        i: usize,
        fg: &FrameGpu,
        timer: &mut StageTimer,
    ) -> Result<MethodOutput> {
        let state = self.built(i, fg)?;
        state.reset(fg)?;
        state.run(fg, timer, false)
    }

    /// Candidate `i`'s state, built on first use (its pipelines and map).
    fn built(&mut self, i: usize, fg: &FrameGpu) -> Result<&mut Box<dyn MethodState>> {
        if self.states[i].is_none() {
            self.states[i] = Some(self.methods[i].build(fg)?);
        }
        Ok(self.states[i].as_mut().expect("built above"))
    }

    /// Every candidate, in two steps. The screen: each is rendered and predicted against the grid
    /// that met the target (σ ≈ T, so only a rough reading); one over `screen` or slower than
    /// that grid's try is out. Then, if any is left, `reference` renders the finer grid into V
    /// and those left are predicted against it, and taken where `accept(F, handed)` (auto's
    /// rule; `handed` for the filter the previous frame of a sequence chose). V is left holding
    /// what the frame renders: the chosen candidate's, else the grid that met the target.
    pub(crate) fn check(
        &mut self,
        at: &Scope,
        timer: &mut StageTimer,
        rule: Against,
        reference: &mut dyn FnMut(&mut StageTimer) -> Result<Option<Reference>>,
    ) -> Result<Outcome> {
        let (fg, geometry) = (at.fg, at.geometry);
        let Against {
            met,
            screen,
            accept,
            handed_on,
        } = rule;
        let v_met = read_v(fg, timer)?;
        let (mut checks, mut maps) = (Vec::new(), 0);
        for i in 0..self.methods.len() {
            let (m, v, ms) = self.render_read(i, fg, timer)?;
            maps += m;
            let screened = predicted(&v, &v_met, geometry, met.rmse).0;
            checks.push(Check {
                method: self.label(i),
                maps: m,
                ms,
                screened,
                difference: None,
                predicted_rmse: None,
                accepted: false,
            });
        }
        let left: Vec<usize> = (0..checks.len())
            .filter(|&i| checks[i].screened <= screen && checks[i].ms < met.ms)
            .collect();
        let r = if left.is_empty() {
            None
        } else {
            reference(timer)?
        };
        let Some(r) = r else {
            fg.ctx
                .queue
                .write_buffer(&fg.visibility, 0, bytemuck::cast_slice(&v_met));
            return Ok(Outcome {
                chosen: None,
                checks,
                maps,
                reference: None,
            });
        };
        maps += r.maps;
        let v_r = read_v(fg, timer)?;
        let mut chosen = None::<(usize, f64, Vec<f32>)>;
        for &i in &left {
            let (m, v, _) = self.render_read(i, fg, timer)?;
            maps += m;
            let (f, d) = predicted(&v, &v_r, geometry, r.rmse);
            let c = &mut checks[i];
            (c.difference, c.predicted_rmse) = (Some(d), Some(f));
            c.accepted = accept(f, handed_on == Some(self.methods[i].name()));
            if c.accepted && chosen.as_ref().is_none_or(|x| f < x.1) {
                chosen = Some((i, f, bound(&v, &v_r, &r.bound)));
            }
        }
        maps += self.leave_in_v(
            (chosen.as_ref().map(|c| c.0), left.last().copied()),
            &v_met,
            fg,
            timer,
        )?;
        Ok(Outcome {
            chosen,
            checks,
            maps,
            reference: Some(r.record),
        })
    }

    /// Where no grid reaches the target: each candidate read against the grid the frame renders
    /// (the last tried, V now). One that differs from it by at most the grid's own predicted
    /// RMSE (D ≤ σ, KEEP × σ for the filter handed on) and rendered quicker than its try is
    /// taken, the closest first. No grid is predicted to err less, so there is no reference to
    /// read F against: D ≤ σ is where F reads 0, the filter no worse than the grid as far as the
    /// estimate can tell, and |V_f − V| ≤ |V_f − V_grid| + |V_grid − V| still bounds it. F itself
    /// is not enough here: on `grazing-ground` pcss at 1024² read 0.060 against a grid predicted
    /// at 0.234, and errs 0.27 (their errors share the acne). V is left holding what the frame
    /// renders.
    pub(crate) fn check_out_of_reach(
        &mut self,
        at: &Scope,
        timer: &mut StageTimer,
        rule: OutOfReach,
    ) -> Result<Outcome> {
        let (fg, geometry) = (at.fg, at.geometry);
        let OutOfReach {
            met,
            bound: met_bound,
            keep,
            handed_on,
        } = rule;
        let v_met = read_v(fg, timer)?;
        let (mut checks, mut maps) = (Vec::new(), 0);
        let mut chosen = None::<(usize, f64, Vec<f32>)>;
        for i in 0..self.methods.len() {
            let (m, v, ms) = self.render_read(i, fg, timer)?;
            maps += m;
            let (f, d) = predicted(&v, &v_met, geometry, met.rmse);
            let limit = if handed_on == Some(self.methods[i].name()) {
                keep * met.rmse
            } else {
                met.rmse
            };
            let accepted = ms < met.ms && d <= limit;
            checks.push(Check {
                method: self.label(i),
                maps: m,
                ms,
                screened: f,
                difference: Some(d),
                predicted_rmse: Some(f),
                accepted,
            });
            if accepted && chosen.as_ref().is_none_or(|x| d < x.1) {
                chosen = Some((i, d, bound(&v, &v_met, met_bound)));
            }
        }
        maps += self.leave_in_v(
            (
                chosen.as_ref().map(|c| c.0),
                self.methods.len().checked_sub(1),
            ),
            &v_met,
            fg,
            timer,
        )?;
        Ok(Outcome {
            chosen,
            checks,
            maps,
            reference: None,
        })
    }

    /// V holds candidate `last`'s (the pair's second): put there what the frame renders, the chosen candidate's
    /// (rendered again unless it is that one) or the grid's `v_met`. The maps it rendered.
    fn leave_in_v(
        &mut self,
        (chosen, last): (Option<usize>, Option<usize>),
        v_met: &[f32],
        fg: &FrameGpu,
        timer: &mut StageTimer,
    ) -> Result<u32> {
        match chosen {
            Some(i) if Some(i) == last => Ok(0),
            Some(i) => self.run_into_cleared(i, fg, timer),
            None => {
                fg.ctx
                    .queue
                    .write_buffer(&fg.visibility, 0, bytemuck::cast_slice(v_met));
                Ok(0)
            }
        }
    }

    /// Candidate `i` into V cleared first: its maps (a first render's warm-up included), V, and
    /// the wall clock of the timed render to V read back.
    fn render_read(
        &mut self,
        i: usize,
        fg: &FrameGpu,
        timer: &mut StageTimer,
    ) -> Result<(u32, Vec<f32>, f64)> {
        // Built and run once before the clock: the time set against the grid's try is what a
        // settled frame pays. Timed with its build, pcss took 2.9–5.4 ms on an H200 against
        // 0.4–0.6 ms without, and lost to grid tries of 1.3–5.9 ms; on lavapipe a first run
        // takes about twice a later one (msm at 64²: 16 against 7 ms).
        let warm = if self.states[i].is_none() {
            let maps = self.run_into_cleared(i, fg, timer)?;
            read_v(fg, timer)?; // submitted and waited for, so the clock below holds none of it
            maps
        } else {
            0
        };
        let start = std::time::Instant::now();
        let maps = self.run_into_cleared(i, fg, timer)?;
        let v = read_v(fg, timer)?;
        Ok((warm + maps, v, start.elapsed().as_secs_f64() * 1e3))
    }

    /// Candidate `i` into V cleared first; its maps.
    fn run_into_cleared(&mut self, i: usize, fg: &FrameGpu, timer: &mut StageTimer) -> Result<u32> {
        // Pending passes (the grid's) go first: the clear is submitted on its own.
        timer.flush(fg.ctx);
        fg.clear_visibility();
        Ok(self.run(i, fg, timer)?.shadow_maps)
    }
}

/// The frame's V as it stands, after what is pending.
pub(crate) fn read_v(fg: &FrameGpu, timer: &mut StageTimer) -> Result<Vec<f32>> {
    timer.flush(fg.ctx);
    timer.cpu(Stage::READBACK, || {
        readback::read_buffer(fg.ctx, &fg.visibility, fg.pixel_count() as u64 * 4)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_filters_prediction_takes_the_grids_error_out_of_the_difference() {
        let geometry = [true, true, true, false];
        // D² = (0.05² + 0.05² + 0) / 3 = 0.001667; σ = 0.02: sqrt(0.001667 − 0.0004) = 0.0356.
        let (p, d) = predicted(
            &[0.55, 0.45, 0.3, 9.0],
            &[0.5, 0.5, 0.3, 0.0],
            &geometry,
            0.02,
        );
        assert!((d - (0.005f64 / 3.0).sqrt()).abs() < 1e-7, "{d}");
        assert!((p - (0.005f64 / 3.0 - 0.0004).sqrt()).abs() < 1e-7, "{p}");
        // A grid predicted to err more than the two differ: the filter is read as exact.
        assert_eq!(
            predicted(
                &[0.55, 0.45, 0.3, 0.0],
                &[0.5, 0.5, 0.3, 0.0],
                &geometry,
                0.1
            )
            .0,
            0.0
        );
        // Values past [0, 1] are clamped, as the frame's V is.
        assert_eq!(predicted(&[1.2], &[1.0], &[true], 0.0).1, 0.0);
        let b = bound(
            &[0.55, 0.45, 0.3, 9.0],
            &[0.5, 0.5, 0.3, 0.0],
            &[0.1, 0.2, 0.01, 0.0],
        );
        assert!(
            (b[0] - 0.15).abs() < 1e-6 && (b[1] - 0.25).abs() < 1e-6 && (b[2] - 0.01).abs() < 1e-6,
            "{b:?}"
        );
        assert_eq!(b[3], 0.0, "no bound off geometry");
    }

    #[test]
    fn the_list_takes_one_map_methods_only() {
        assert!(parse_list("none").unwrap().is_empty());
        let l = parse_list("pcss+msm").unwrap();
        assert_eq!(
            l.iter().map(|m| m.name()).collect::<Vec<_>>(),
            vec!["pcss", "msm"]
        );
        for (bad, why) in [
            ("regular", "not a filtered one-map method"),
            ("hard", "not a filtered one-map method"),
            ("pcss+pcss", "twice"),
            ("pcs", "not a method"),
            ("", "not a method"),
        ] {
            let e = parse_list(bad)
                .err()
                .unwrap_or_else(|| panic!("{bad} parsed"))
                .to_string();
            assert!(e.contains(why) && e.contains("filters"), "{bad}: {e}");
        }
    }
}
