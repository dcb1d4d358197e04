//! `hold = on`: a certified frame starts each class from the setting the previous frame ended
//! on, so a class's setting changes only where its measured error asks for it. The plan is
//! decided again every frame from the blocker search, whose class sizes move with the camera;
//! deciding afresh each frame changed tiles' settings, and with them their V, from frame to frame
//! (results/regions-popping/). A held frame measures the kept settings on its own draws and
//! steps up from them where the frame's bound is over T. The way down is the filter, whose V the
//! frame renders and traces anyway: a grid class takes it where the frame's bound with the
//! filter's stays below T / BAND (`methods::hold`), so a class that went down does not come
//! straight back up on the next frame's noise.

use super::{certified_on, frame_bound, part, test, Class, Measure, Setting};
use crate::certify::Certificate;
use crate::gpu::timing::StageTimer;
use crate::methods::hold::BAND;
use crate::methods::regions::record::RegionsRecord;
use crate::methods::regions::{window_extent, Group, State};
use crate::scene::light::Bounds;
use crate::stages::FrameGpu;
use crate::Result;

/// The settings a frame ended on, by class, that the next frame starts from (empty: the next
/// frame decides afresh).
#[derive(Clone, Debug, Default, PartialEq)]
pub(in crate::methods::regions) struct Settled(Vec<(usize, Setting)>);

impl Settled {
    /// What the next frame starts from after a frame whose classes ended as `classes`: their
    /// best settings.
    pub(super) fn after(classes: &[Class]) -> Settled {
        Settled(
            classes
                .iter()
                .filter_map(|cl| Some((cl.class, cl.best.as_ref()?.0)))
                .collect(),
        )
    }

    pub(in crate::methods::regions) fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    fn get(&self, class: usize) -> Option<Setting> {
        self.0.iter().find(|(c, _)| *c == class).map(|(_, s)| *s)
    }

    /// As the state's memory keeps it: `[class, n, size]` per class, n = 0 for the filter.
    pub(in crate::methods::regions) fn to_json(&self) -> serde_json::Value {
        let rows: Vec<[u64; 3]> = self
            .0
            .iter()
            .map(|&(c, s)| match s {
                Setting::Filter => [c as u64, 0, 0],
                Setting::Grid { n, size } => [c as u64, n as u64, size as u64],
            })
            .collect();
        serde_json::json!(rows)
    }

    /// The settings `to_json` wrote (rows that do not read as three numbers are left out).
    pub(in crate::methods::regions) fn from_json(v: &serde_json::Value) -> Settled {
        let row = |r: &serde_json::Value| -> Option<(usize, Setting)> {
            let (c, n, size) = (r[0].as_u64()?, r[1].as_u64()?, r[2].as_u64()?);
            let setting = match n {
                0 => Setting::Filter,
                n => Setting::Grid {
                    n: n as u32,
                    size: size as u32,
                },
            };
            Some((c as usize, setting))
        };
        Settled(v.as_array().into_iter().flatten().filter_map(row).collect())
    }
}

impl State {
    /// A held frame's settings: each class the one it ended on last frame; a class new this
    /// frame the filter where its own bound is within T, else its plan. The grids are rendered
    /// by (n, size), each over the union of its classes' own windows (held from frame to frame
    /// as the plan's are), and every class is measured on its setting. Returns V as rendered.
    pub(super) fn held_choice(
        &mut self,
        fg: &FrameGpu,
        timer: &mut StageTimer,
        m: &mut Measure,
        settled: &Settled,
        words: &[u32],
        record: &mut RegionsRecord,
    ) -> Result<Vec<f32>> {
        let target = self.method.target as f64;
        for cl in m.classes.iter_mut() {
            cl.setting = match (settled.get(cl.class), &m.v_filter) {
                (Some(Setting::Filter), Some(v)) => {
                    test(cl, Setting::Filter, v, m.delta);
                    Setting::Filter
                }
                (Some(grid @ Setting::Grid { .. }), _) => grid,
                (_, Some(v)) => {
                    test(cl, Setting::Filter, v, m.delta);
                    if cl.current <= target {
                        Setting::Filter
                    } else {
                        cl.plan
                    }
                }
                (_, None) => cl.plan,
            };
        }
        let mut groups = grids_of(&m.classes);
        for g in groups.iter_mut() {
            g.extent = window_extent(fg, &g.window);
        }
        if groups.is_empty() {
            record.classes = Vec::new();
            self.classes.clear();
            return Ok(m.v_filter.clone().unwrap_or_default());
        }
        let v = self.render_read(fg, timer, m, &mut groups, words, record)?;
        for cl in m.classes.iter_mut() {
            if let s @ Setting::Grid { .. } = cl.setting {
                test(cl, s, &v, m.delta);
            }
        }
        if let Some(f) = &m.v_filter {
            down_to_filter(&mut m.classes, m.geometry_pixels, f, m.delta, target / BAND);
        }
        Ok(v)
    }
}

/// The way down: grid classes take the filter's V, the dearest grid first (its maps × texels),
/// while the frame's bound with it stays at most `floor` (T / BAND).
fn down_to_filter(
    classes: &mut [Class],
    geometry_pixels: usize,
    v: &[f32],
    delta: f64,
    floor: f64,
) {
    let filter: Vec<Option<(Certificate, Vec<f32>)>> = classes
        .iter()
        .map(|cl| matches!(cl.setting, Setting::Grid { .. }).then(|| certified_on(cl, v, delta)))
        .collect();
    let bounds: Vec<Option<f64>> = filter
        .iter()
        .map(|f| f.as_ref().map(|(c, _)| c.bound))
        .collect();
    for i in going_down(classes, &bounds, geometry_pixels, floor) {
        let (cert, pixels) = filter[i].clone().expect("a grid class's filter bound");
        let cl = &mut classes[i];
        cl.tried.push((super::label(Setting::Filter), cert.bound));
        cl.setting = Setting::Filter;
        cl.best = Some((Setting::Filter, cert, pixels));
    }
}

/// Which grid classes go down to the filter, given each class's filter bound (None: not a
/// candidate): the dearest grid first, each where the frame's bound with the filter's in its
/// place stays at most `floor`.
fn going_down(
    classes: &[Class],
    filter: &[Option<f64>],
    geometry_pixels: usize,
    floor: f64,
) -> Vec<usize> {
    let mut order: Vec<(f64, usize)> = classes
        .iter()
        .enumerate()
        .filter_map(|(i, cl)| match (cl.setting, filter[i]) {
            (Setting::Grid { n, size }, Some(_)) => Some(((n as f64 * size as f64).powi(2), i)),
            _ => None,
        })
        .collect();
    order.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut mse = frame_bound(classes, geometry_pixels).powi(2);
    let mut down = Vec::new();
    for (_, i) in order {
        let cl = &classes[i];
        let share = cl.design.pixel_count() as f64 / geometry_pixels as f64;
        let moved =
            mse - part(cl, geometry_pixels) + share * filter[i].expect("kept above").powi(2);
        if moved <= floor * floor {
            mse = moved;
            down.push(i);
        }
    }
    down
}

/// The grid classes as groups, one per (n, size): their tiles, the finest texel any needs and
/// the union of their own windows (extent left for the caller, which has the frame).
fn grids_of(classes: &[Class]) -> Vec<Group> {
    let mut groups: Vec<Group> = Vec::new();
    for cl in classes {
        let Setting::Grid { n, size } = cl.setting else {
            continue;
        };
        match groups.iter_mut().find(|g| (g.n, g.size) == (n, size)) {
            Some(g) => {
                g.classes.push(cl.class);
                g.tiles += cl.own.tiles;
                g.texel_need = g.texel_need.min(cl.own.texel_need);
                g.window = Bounds {
                    min: g.window.min.min(cl.own.window.min),
                    max: g.window.max.max(cl.own.window.max),
                };
            }
            None => groups.push(Group {
                n,
                size,
                classes: vec![cl.class],
                ..cl.own
            }),
        }
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::super::split::tests::class;
    use super::*;

    #[test]
    fn a_grid_class_goes_down_only_while_the_frame_stays_within_t_over_the_band() {
        // T = 0.03, floor T / 1.15 = 0.026087, floor² = 6.805e-4. Each class is on its grid at
        // bound 0.02 (frame MSE 4e-4); their filter bounds 0.025 and 0.04. Down with the first
        // (half the pixels): 0.5·4e-4 + 0.5·6.25e-4 = 5.125e-4 ≤ floor². Then the second:
        // 0.5·6.25e-4 + 0.5·1.6e-3 = 1.1125e-3 > floor²: it stays on its grid.
        let mut classes = vec![class(0, 50, 0.02, 1e6), class(1, 50, 0.02, 1e6)];
        for cl in classes.iter_mut() {
            cl.setting = cl.plan;
            let cert = cl.best.take().unwrap().1;
            cl.best = Some((cl.plan, cert, Vec::new()));
        }
        let filter = [Some(0.025), Some(0.04)];
        assert_eq!(going_down(&classes, &filter, 100, 0.03 / BAND), vec![0]);
        // The dearer grid is tried first: with the second class on 8 × 8 maps it goes first
        // (0.5·4e-4 + 0.5·1.6e-3 = 1e-3 > floor², so it stays), and the first still goes.
        classes[1].setting = Setting::Grid { n: 8, size: 512 };
        assert_eq!(going_down(&classes, &filter, 100, 0.03 / BAND), vec![0]);
        let filter = [Some(0.04), Some(0.025)];
        assert_eq!(going_down(&classes, &filter, 100, 0.03 / BAND), vec![1]);
        // Where neither filter fits under the floor (0.5·4e-4 + 0.5·1.225e-3 = 8.125e-4), none
        // moves.
        let filter = [Some(0.035), Some(0.035)];
        assert!(going_down(&classes, &filter, 100, 0.03 / BAND).is_empty());
        // A class without a filter bound (no filter, or on the filter) is no candidate.
        assert!(going_down(&classes, &[None, None], 100, 0.03 / BAND).is_empty());
    }

    #[test]
    fn settled_settings_read_back_as_written() {
        let s = Settled(vec![
            (0, Setting::Filter),
            (2, Setting::Grid { n: 6, size: 1024 }),
        ]);
        assert_eq!(Settled::from_json(&s.to_json()), s);
        assert_eq!(s.get(2), Some(Setting::Grid { n: 6, size: 1024 }));
        assert_eq!(s.get(1), None);
        // A row that is not three numbers is left out, not read as a setting.
        let v = serde_json::json!([[1, 4, 512], ["x", 1, 1], [3]]);
        assert_eq!(
            Settled::from_json(&v),
            Settled(vec![(1, Setting::Grid { n: 4, size: 512 })])
        );
    }
}
