//! A fresh frame's settings: which classes keep the filter (`filter_split`), the plan's grids
//! for the rest, or the frame-wide grid where it is predicted about as cheap.

use super::{frame_bound, test, Class, Measure, Setting};
use crate::gpu::timing::StageTimer;
use crate::methods::regions::record::{FallbackRecord, RegionsRecord};
use crate::methods::regions::{Group, State};
use crate::stages::FrameGpu;
use crate::Result;

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

impl State {
    /// The fresh settings (steps 3–5 of docs/regions.md, "Certified classes"): every class
    /// bounded on the filter's V and the split keeping it where the frame's budget lets it stay
    /// (where it fits every class, it is the frame); the plan's grids for the others, or the
    /// frame-wide grid where it costs at most `fallback` times their plan; those rendered and
    /// measured. Returns V as rendered and the fallback's record.
    pub(super) fn fresh_choice(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        m: &mut Measure,
        class_groups: &[Group],
        words: &[u32],
        record: &mut RegionsRecord,
    ) -> Result<(Vec<f32>, FallbackRecord)> {
        let target = self.method.target as f64;
        if let Some(v) = &m.v_filter {
            for cl in m.classes.iter_mut() {
                test(cl, Setting::Filter, v, m.delta);
            }
        }
        filter_split(&mut m.classes, m.geometry_pixels, target);
        let classes = &mut m.classes;
        let all_filter = !classes.is_empty()
            && classes.iter().all(|cl| cl.setting == Setting::Filter)
            && frame_bound(classes, m.geometry_pixels) <= target;
        let planned: Vec<Group> = class_groups
            .iter()
            .filter(|g| {
                !classes
                    .iter()
                    .any(|cl| cl.class == g.classes[0] && cl.setting == Setting::Filter)
            })
            .map(|g| Group {
                classes: g.classes.clone(),
                ..*g
            })
            .collect();
        let mut groups = if self.method.merge {
            self.merged(fg, planned)
        } else {
            planned
        };
        let plan_cost: f64 = groups.iter().map(|g| self.cost(g)).sum();
        let frame_wide = self.frame_wide(fg, class_groups);
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
        let record_fallback = FallbackRecord {
            taken: fallback.is_some(),
            setting: fallback.clone(),
            plan_cost: Some(plan_cost),
            frame_wide_cost: Some(frame_cost),
            ratio: self.method.fallback,
        };
        let mut v = m.v_filter.clone().unwrap_or_default();
        if all_filter || groups.is_empty() {
            record.classes = Vec::new();
            self.classes.clear();
            return Ok((v, record_fallback));
        }
        v = self.render_read(fg, timer, m, &mut groups, words, record)?;
        for group in &groups {
            for cl in m
                .classes
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
                test(cl, s, &v, m.delta);
            }
        }
        Ok((v, record_fallback))
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
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::certify::bound::BoundKind;
    use crate::certify::design::{self, Design};
    use crate::certify::Certificate;
    use crate::scene::light::Bounds;

    /// A class of `pixels` geometry pixels (of a 100-pixel frame) whose filter's bound is `filter`.
    pub(in crate::methods::regions) fn class(
        c: usize,
        pixels: usize,
        filter: f64,
        plan_cost: f64,
    ) -> Class {
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
