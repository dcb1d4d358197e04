//! Step-ups: while the frame's bound is over T, the classes over T that hold most of the excess
//! step up a rung (more samples, a finer map, on their own windows; a filter class to its plan),
//! as many as the step model predicts the budget needs, and are measured again on the same draws.

use super::{frame_bound, part, test, Class, Measure, Setting};
use crate::gpu::timing::StageTimer;
use crate::methods::auto::filter::read_v;
use crate::methods::regions::{held_window, window_extent, Group, State, LADDER};
use crate::stages::FrameGpu;
use crate::Result;

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

/// The next half-octave side above `size`, at most `max`. Found among the sides themselves:
/// from a power of two, size·√2 is exactly the next half-octave, and rounding it up by the log
/// landed a whole octave higher (64 → 128), a step 2× the texels the rung's model prices.
fn half_octave_up(size: u32, max: u32) -> u32 {
    crate::methods::regions::half_octave_sides()
        .find(|&s| s > size)
        .unwrap_or(max)
        .min(max)
}

impl State {
    /// Rounds of steps until the frame's bound is at most T or the classes' ladders end: each
    /// round renders its classes alone, on their own windows, between clears (`step_round`).
    pub(super) fn step_rounds(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        m: &mut Measure,
        words: &[u32],
    ) -> Result<()> {
        let target = self.method.target as f64;
        while frame_bound(&m.classes, m.geometry_pixels) > target {
            let steps = self.step_round(&mut m.classes, m.geometry_pixels);
            let mut round: Vec<(Step, Group, f64)> = Vec::new();
            for st in steps {
                let Some((n, size)) = st.at else { continue };
                let cl = &mut m.classes[st.class];
                let before = cl.current;
                cl.setting = Setting::Grid { n, size };
                cl.steps += 1;
                let mut group = Group {
                    n,
                    classes: vec![cl.class],
                    size,
                    extent: window_extent(fg, &cl.own.window),
                    ..cl.own
                };
                // A stepped class keeps the previous frame's window too (`hold`).
                if self.method.hold {
                    held_window(&m.previous, fg, &mut group);
                }
                round.push((st, group, before));
            }
            if round.is_empty() {
                break;
            }
            fg.clear_visibility();
            for (k, (_, group, _)) in round.iter().enumerate() {
                let out = self.render_group(fg, timer, k, group, words)?;
                m.maps += out.shadow_maps;
                m.syncs += out.syncs;
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
            m.syncs += 1;
            for (st, group, before) in &round {
                if self.method.hold {
                    self.held.retain(|h| (h.0, h.1) != (group.n, group.size));
                    self.held.push((group.n, group.size, group.window));
                }
                let s = Setting::Grid {
                    n: group.n,
                    size: group.size,
                };
                let cl = &mut m.classes[st.class];
                test(cl, s, &stepped, m.delta);
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
        Ok(())
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
}

#[cfg(test)]
mod tests {
    use super::half_octave_up;

    #[test]
    fn a_texel_rung_is_half_an_octave() {
        let steps: Vec<(u32, u32)> = [64, 96, 128, 192, 1024, 1456, 2048]
            .into_iter()
            .map(|s| (s, half_octave_up(s, 2048)))
            .collect();
        assert_eq!(
            steps,
            [
                (64, 96),
                (96, 128),
                (128, 192),
                (192, 256),
                (1024, 1456),
                (1456, 2048),
                (2048, 2048)
            ]
        );
    }
}
