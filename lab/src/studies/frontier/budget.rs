//! The error budget's rows against the oracle (docs/budget.md): measured/T, what the row reported
//! (met, or the best predicted error where the target is out of reach), and time/oracle, the
//! oracle being the cheapest fixed setting whose measured RMSE is at most T; and the calibration
//! chart of the rows' predicted against measured RMSE.

use super::{FrontierJob, FrontierLine};
use crate::gpu::GpuContext;
use crate::record::measure;
use crate::studies::calibration::charts::calibration_svg;
use crate::studies::calibration::half;
use crate::studies::estimate::charts::EstimatePoint;
use crate::Result;
use serde::{Deserialize, Serialize};

/// The promise: measured RMSE at most T on this share of rows …
pub const MET_SHARE: f64 = 0.95;
/// … and time at most this many times the oracle's on this share.
pub const TIME_RATIO: f64 = 1.3;
pub const TIME_SHARE: f64 = 0.90;

/// What a budget row's own record says.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Reading {
    /// The calibrated predicted RMSE the frame reports (the best predicted where out of reach).
    pub predicted: f64,
    pub target_met: bool,
    /// The frame that chose: its tries' wall clock, and its certified decision's (the exact
    /// pixels and the candidates it rendered), ms.
    pub search_ms: f64,
    pub tries: usize,
    /// Decided by the certified bound (docs/certify.md): `predicted` is the chosen candidate's
    /// bound (the least tested where out of reach).
    #[serde(default)]
    pub certified: bool,
}

impl Reading {
    pub fn of(record: &serde_json::Value) -> Reading {
        match crate::methods::auto::AutoRecord::read(record) {
            Some(a) => Reading {
                predicted: a.reported(),
                target_met: a.target_met,
                search_ms: a.decision_ms(),
                tries: a.tries.len(),
                certified: a.certified.is_some(),
            },
            // Not auto's record: nothing it reported.
            None => Reading {
                predicted: f64::NAN,
                target_met: false,
                search_ms: 0.0,
                tries: 0,
                certified: false,
            },
        }
    }

    /// What the row reported: `met (0.0181)`, `met (bound 0.0181)`, or not met with the best.
    pub fn reported(&self) -> String {
        match (self.target_met, self.certified) {
            (true, false) => format!("met ({:.5})", self.predicted),
            (true, true) => format!("met (bound {:.5})", self.predicted),
            (false, false) => format!("not met: best predicted {:.5}", self.predicted),
            (false, true) => format!("not met: least bound {:.5}", self.predicted),
        }
    }
}

/// A budget row and its oracle timed side by side: one measure window under the oracle's maps,
/// their frames interleaved round by round, so both see the same load. Timed in their own windows
/// (the fixed settings per map configuration, the budget rows in theirs), the same setting read
/// 7.8 times slower as `auto`'s choice than as the oracle on a shared CPU device
/// (results/budget-promise/, `analytic-square` at 0.03: `pcss` both).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Paired {
    pub ms: f64,
    pub oracle_ms: f64,
}

/// Times each `auto` row with an oracle against it (`Paired`). `auto` chooses its own grid, so the
/// oracle's maps leave its choice as it was, except for a one-map filter, which renders at the
/// scene's size: a row whose maps differ from its own window's is left unpaired, and says so.
pub fn pair(
    ctx: &GpuContext,
    job: &FrontierJob,
    lines: &mut [FrontierLine],
    log: &dyn Fn(&str),
) -> Result<()> {
    let find = |setting: &str| {
        job.groups.iter().find_map(|g| {
            g.specs
                .iter()
                .position(|s| format!("{s} @ {}", g.maps.label()) == setting)
                .map(|k| (g, k))
        })
    };
    for l in lines.iter_mut() {
        let (Some(_), Some(oracle)) = (&l.budget, &l.oracle) else {
            continue;
        };
        let (Some((ga, ka)), Some((go, ko))) = (find(&l.setting()), find(oracle)) else {
            continue;
        };
        let scene = go.maps.apply(job.scene, 0.25);
        let methods = [ga.methods[ka].clone(), go.methods[ko].clone()];
        let measured = measure::measure(
            ctx,
            &scene,
            &methods,
            job.repeats,
            &mut |_, _, _| {},
            &mut |_, f| Ok(f.output.shadow_maps),
        )?;
        match &measured[..] {
            [Ok(a), Ok(o)] if a.judged == l.core.maps => {
                l.paired = Some(Paired {
                    ms: a.timing.median_ms,
                    oracle_ms: o.timing.median_ms,
                })
            }
            [Ok(a), Ok(_)] => log(&format!(
                "{}: under {}'s maps it rendered {} maps, not {}: time/oracle from the windows",
                l.setting(),
                oracle,
                a.judged,
                l.core.maps
            )),
            _ => log(&format!(
                "{}: side-by-side timing against {oracle} failed: time/oracle from the windows",
                l.setting()
            )),
        }
    }
    Ok(())
}

/// The table and its counts against the promise.
pub fn table(lines: &[FrontierLine], budget: &[&FrontierLine]) -> String {
    let mut s = String::from(
        "\nThe oracle: the cheapest fixed setting whose measured RMSE is at most the target, what a method that knew the truth would render. \
         `reported`: what the row's run.json says (met, with its certified bound or its predicted error, or not met with the least); `search ms`: the tries and the certified decision of the frame that chose (the timed frames render the chosen setting alone); `time/oracle`: the row and its oracle timed side by side (`*`: from their own windows, where pairing could not run).\n\n\
         | setting | maps | RMSE | measured/T | reported | median ms | search ms | oracle | its RMSE/T | its ms | time/oracle |\n|---|---:|---:|---:|---|---:|---:|---|---:|---:|---:|\n",
    );
    let (mut under, mut quick, mut timed, mut false_met, mut reachable_under) = (0, 0, 0, 0, 0);
    // The promise is auto's: rows without a budget reading (regions:target=T, which budgets only
    // its samples) stay in the frontier's budget section above, not in these counts.
    let budget: Vec<&FrontierLine> = budget
        .iter()
        .copied()
        .filter(|l| l.budget.is_some())
        .collect();
    for l in &budget {
        let Some(target) = l.target() else { continue };
        let r = l.budget.clone().unwrap_or_default();
        under += usize::from(l.core.rmse <= target);
        false_met += usize::from(r.target_met && l.core.rmse > target);
        let reported = r.reported();
        let o = l
            .oracle
            .as_ref()
            .and_then(|b| lines.iter().find(|o| &o.setting() == b));
        let (name, e, t, ratio) = match o {
            Some(o) => {
                let (ratio, mark) = l
                    .paired
                    .map_or((l.core.frame_ms / o.core.frame_ms, "*"), |p| {
                        (p.ms / p.oracle_ms, "")
                    });
                timed += 1;
                quick += usize::from(ratio <= TIME_RATIO);
                reachable_under += usize::from(l.core.rmse <= target);
                (
                    o.setting(),
                    format!("{:.2}", o.core.rmse / target),
                    format!("{:.1}", o.core.frame_ms),
                    format!("{ratio:.2}{mark}"),
                )
            }
            None => ("none reaches it".into(), "-".into(), "-".into(), "-".into()),
        };
        s += &format!("| {} | {} | {:.5} | {:.2} | {reported} | {:.1} | {:.0} | {name} | {e} | {t} | {ratio} |\n", l.core.spec, l.core.maps, l.core.rmse, l.core.rmse / target, l.core.frame_ms, r.search_ms);
    }
    let n = budget.len();
    s += &format!(
        "\nMeasured RMSE at most the target: {under} of {n} (the promise: {:.0}%); {reachable_under} of the {timed} rows some fixed setting reaches. Time at most {TIME_RATIO} × the oracle's: {quick} of {timed} rows with an oracle (the promise: {:.0}%). Reported met while measured over the target: {false_met}.\n",
        MET_SHARE * 100.0,
        TIME_SHARE * 100.0
    );
    s
}

/// The budget rows' reported (calibrated) prediction against their measured RMSE, the series
/// the scene's half of the calibration's split.
pub fn chart(budget: &[&FrontierLine]) -> Option<String> {
    let points: Vec<EstimatePoint> = budget
        .iter()
        .filter_map(|l| {
            let r = l.budget.as_ref()?;
            Some(EstimatePoint {
                layout: format!("{} half", half(&l.core.scene).name())
                    .replace("held out half", "held out"),
                label: l.core.spec.clone(),
                measured: l.core.rmse,
                predicted: r.predicted,
            })
        })
        .collect();
    calibration_svg(
        &format!(
            "{}: the budget's predicted against measured RMSE of V",
            budget.first()?.core.scene
        ),
        &points,
    )
    .ok()
}
