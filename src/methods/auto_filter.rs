//! auto's single-map check (docs/error-estimate.md §6): once a grid meets the target, each
//! candidate one-map method (`filters`, pcss by default) is rendered and set against the V of a
//! finer grid, one predicted to err by half the target. The estimate has no reading of a filter's
//! own error, but that grid is a reference whose error it does know: the grid's and the filter's
//! errors come from unrelated causes (where the points fall, against one map's blocker estimate),
//! so with D the RMS over geometry pixels of their difference and σ the grid's predicted RMSE,
//! the filter's RMSE is predicted as sqrt(D² − σ²); per pixel, |V_f − V| ≤ |V_f − V_grid| +
//! |V_grid − V| bounds it by the difference plus the grid's bound. A filter predicted to meet the
//! target that took less time than the grid that met it is what the frame renders, and the
//! settled frames after it.

use super::{Family, Method, MethodOutput, MethodState};
use crate::gpu::timing::StageTimer;
use crate::gpu::{readback, Stage};
use crate::stages::FrameGpu;
use crate::{Error, Result};

/// `filters = none` or names joined by `+` (`pcss+msm`): one-map methods at their defaults.
pub fn parse_list(text: &str) -> Result<Vec<Method>> {
    if text == "none" {
        return Ok(Vec::new());
    }
    let mut out: Vec<Method> = Vec::new();
    for name in text.split('+') {
        let bad = |why: String| Error::Param(format!("auto: filters = {text}: `{name}` {why}; give one-map methods joined by + (e.g. pcss+msm), or none"));
        let m = Method::parse(name, &[]).map_err(|e| bad(format!("is not a method ({e})")))?;
        if !matches!(m.family(), Family::Pcf | Family::Filtered) || name.contains(':') {
            return Err(bad("is not a filtered one-map method at its defaults".into()));
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
pub fn predicted(v_filter: &[f32], v_grid: &[f32], geometry: &[bool], grid_rmse: f64) -> (f64, f64) {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for ((f, g), _) in v_filter.iter().zip(v_grid).zip(geometry).filter(|(_, m)| **m) {
        let d = f64::from(f.clamp(0.0, 1.0)) - f64::from(g.clamp(0.0, 1.0));
        sum += d * d;
        n += 1;
    }
    let d = (sum / n.max(1) as f64).sqrt();
    ((d * d - grid_rmse * grid_rmse).max(0.0).sqrt(), d)
}

/// Per pixel: |V_f − V_grid| plus the grid's bound (0 off geometry, as the grid's is).
pub fn bound(v_filter: &[f32], v_grid: &[f32], grid_bound: &[f32]) -> Vec<f32> {
    v_filter
        .iter()
        .zip(v_grid)
        .zip(grid_bound)
        .map(|((f, g), b)| if *b > 0.0 { (f.clamp(0.0, 1.0) - g.clamp(0.0, 1.0)).abs() + b } else { 0.0 })
        .collect()
}

/// One candidate's check, as run.json's record keeps it.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Check {
    pub method: String,
    pub maps: u32,
    /// Wall clock from its render to its V read back, ms (the grid's try: `tries[…].ms`).
    pub ms: f64,
    /// RMS of V_f − V_grid over geometry pixels.
    pub difference: f64,
    pub predicted_rmse: f64,
    pub accepted: bool,
}

/// The reference grid (in the frame's V now): its predicted RMSE and its bound; the time of the
/// grid that met the target, which a filter must beat; that grid's V, which the frame renders
/// unless a filter is chosen.
pub struct Grid<'a> {
    pub rmse: f64,
    pub bound: &'a [f32],
    pub ms: f64,
    pub restore: &'a [f32],
}

/// The check's outcome: the chosen candidate with its prediction and bound.
pub struct Outcome {
    pub chosen: Option<(usize, f64, Vec<f32>)>,
    pub checks: Vec<Check>,
    pub maps: u32,
}

/// The candidates and their states (built on first use, then kept for the settled frames).
pub struct Candidates {
    methods: Vec<Method>,
    states: Vec<Option<Box<dyn MethodState>>>,
}

impl Candidates {
    pub fn new(methods: Vec<Method>) -> Candidates {
        let states = methods.iter().map(|_| None).collect();
        Candidates { methods, states }
    }
    pub fn is_empty(&self) -> bool {
        self.methods.is_empty()
    }
    pub fn name(&self, i: usize) -> &'static str {
        self.methods[i].name()
    }
    pub fn label(&self, i: usize) -> String {
        self.methods[i].label()
    }

    /// Candidate `i` rendered into V (which the caller has cleared).
    pub fn run(&mut self, i: usize, fg: &FrameGpu, timer: &mut StageTimer) -> Result<MethodOutput> {
        if self.states[i].is_none() {
            self.states[i] = Some(self.methods[i].build(fg)?);
        }
        let state = self.states[i].as_mut().expect("built above");
        state.reset(fg)?;
        state.run(fg, timer, false)
    }

    /// Every candidate against the reference grid whose V is in the frame's V now. V is left
    /// holding what the frame renders: the chosen candidate's, else `grid.restore`.
    /// `accept(F, handed)`: whether a prediction meets the target (auto's rule, KEEP included). `handed_on`: the filter the
    /// previous frame of a sequence chose, kept within KEEP of the target as a grid is.
    pub fn check(&mut self, fg: &FrameGpu, timer: &mut StageTimer, geometry: &[bool], grid: Grid, accept: &dyn Fn(f64, bool) -> bool, handed_on: Option<&str>) -> Result<Outcome> {
        let bytes = fg.pixel_count() as u64 * 4;
        timer.flush(fg.ctx);
        let v_grid: Vec<f32> = timer.cpu(Stage::READBACK, || readback::read_buffer(fg.ctx, &fg.visibility, bytes))?;
        let (mut checks, mut maps, mut chosen) = (Vec::new(), 0, None::<(usize, f64, Vec<f32>)>);
        for i in 0..self.methods.len() {
            let start = std::time::Instant::now();
            let shadow_maps = self.run_into_cleared(i, fg, timer)?;
            timer.flush(fg.ctx);
            let v: Vec<f32> = timer.cpu(Stage::READBACK, || readback::read_buffer(fg.ctx, &fg.visibility, bytes))?;
            let ms = start.elapsed().as_secs_f64() * 1e3;
            maps += shadow_maps;
            let (predicted_rmse, difference) = predicted(&v, &v_grid, geometry, grid.rmse);
            let accepted = accept(predicted_rmse, handed_on == Some(self.name(i))) && ms < grid.ms;
            checks.push(Check { method: self.label(i), maps: shadow_maps, ms, difference, predicted_rmse, accepted });
            if accepted && chosen.as_ref().is_none_or(|c| predicted_rmse < c.1) {
                chosen = Some((i, predicted_rmse, bound(&v, &v_grid, grid.bound)));
            }
        }
        // V holds the last candidate's: write back what the frame renders, unless it is that one.
        match &chosen {
            Some((i, _, _)) if *i + 1 == self.methods.len() => {}
            Some((i, _, _)) => maps += self.run_into_cleared(*i, fg, timer)?,
            None => fg.ctx.queue.write_buffer(&fg.visibility, 0, bytemuck::cast_slice(grid.restore)),
        }
        Ok(Outcome { chosen, checks, maps })
    }

    /// Candidate `i` into V cleared first; its maps.
    fn run_into_cleared(&mut self, i: usize, fg: &FrameGpu, timer: &mut StageTimer) -> Result<u32> {
        // Pending passes (the grid's) go first: the clear is submitted on its own.
        timer.flush(fg.ctx);
        let mut enc = fg.ctx.device.create_command_encoder(&Default::default());
        enc.clear_buffer(&fg.visibility, 0, None);
        fg.ctx.queue.submit([enc.finish()]);
        Ok(self.run(i, fg, timer)?.shadow_maps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_filters_prediction_takes_the_grids_error_out_of_the_difference() {
        let geometry = [true, true, true, false];
        // D² = (0.05² + 0.05² + 0) / 3 = 0.001667; σ = 0.02: sqrt(0.001667 − 0.0004) = 0.0356.
        let (p, d) = predicted(&[0.55, 0.45, 0.3, 9.0], &[0.5, 0.5, 0.3, 0.0], &geometry, 0.02);
        assert!((d - (0.005f64 / 3.0).sqrt()).abs() < 1e-7, "{d}");
        assert!((p - (0.005f64 / 3.0 - 0.0004).sqrt()).abs() < 1e-7, "{p}");
        // A grid predicted to err more than the two differ: the filter is read as exact.
        assert_eq!(predicted(&[0.55, 0.45, 0.3, 0.0], &[0.5, 0.5, 0.3, 0.0], &geometry, 0.1).0, 0.0);
        // Values past [0, 1] are clamped, as the frame's V is.
        assert_eq!(predicted(&[1.2], &[1.0], &[true], 0.0).1, 0.0);
        let b = bound(&[0.55, 0.45, 0.3, 9.0], &[0.5, 0.5, 0.3, 0.0], &[0.1, 0.2, 0.01, 0.0]);
        assert!((b[0] - 0.15).abs() < 1e-6 && (b[1] - 0.25).abs() < 1e-6 && (b[2] - 0.01).abs() < 1e-6, "{b:?}");
        assert_eq!(b[3], 0.0, "no bound off geometry");
    }

    #[test]
    fn the_list_takes_one_map_methods_only() {
        assert!(parse_list("none").unwrap().is_empty());
        let l = parse_list("pcss+msm").unwrap();
        assert_eq!(l.iter().map(|m| m.name()).collect::<Vec<_>>(), vec!["pcss", "msm"]);
        for (bad, why) in [("regular", "not a filtered one-map method"), ("hard", "not a filtered one-map method"), ("pcss+pcss", "twice"), ("pcs", "not a method"), ("", "not a method")] {
            let e = parse_list(bad).err().unwrap_or_else(|| panic!("{bad} parsed")).to_string();
            assert!(e.contains(why) && e.contains("filters"), "{bad}: {e}");
        }
    }
}
