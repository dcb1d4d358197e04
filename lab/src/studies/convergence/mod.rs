//! The convergence study: one method's error against the reference as its sample count grows
//! (`regular:n=2,3,4,6,8,11,16`: about twice the shadow maps each step), and the fitted order
//! of convergence, the slope of log RMSE against log maps. Monte Carlo sampling of the light
//! falls as maps^-0.5; a stratified grid can do better on smooth penumbrae, and a slope near 0
//! says more samples stopped paying (the map's own error dominates).

pub mod command;

use crate::frame;
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::record::judge::Judge;
use crate::record::row_core::RowCore;
use crate::reference::truth::{self, Cache};
use crate::reference::ReferenceMode;
use crate::scene::Scene;
use crate::{Error, Result};

pub struct ConvergenceJob<'a> {
    pub scene: &'a Scene,
    /// The method spec without the swept key, e.g. `regular:layout=centred`.
    pub spec: String,
    /// The swept parameter and its values, in the order given.
    pub key: String,
    pub values: Vec<String>,
    pub reference: ReferenceMode,
    pub cache: Cache,
}

/// One value of the swept parameter: the frame's shadow maps and its error over geometry pixels.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ConvergenceRow {
    /// Scene, the label as spec, method, params, maps, map size, RMSE over geometry pixels,
    /// adapter, build; `frame_ms` 0: the study times no frame (its files stay the same from run
    /// to run).
    #[serde(flatten)]
    pub core: RowCore,
    pub value: String,
    pub label: String,
    pub mae: f64,
    /// The value failed at run time (an overflow, out of memory, a map over the budget): the
    /// reason. Its figures are zero and mean nothing; the fit and the table skip it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
}

#[derive(Debug, serde::Serialize)]
pub struct ConvergenceOutcome {
    pub scene: String,
    /// The method spec without the swept key.
    pub method: String,
    pub key: String,
    pub reference: String,
    pub rows: Vec<ConvergenceRow>,
    /// Least-squares slope of ln RMSE on ln maps; `None` with fewer than two distinct map counts
    /// with a non-zero error.
    pub slope: Option<f64>,
}

/// Each value's method, parsed and checked against the scene's light before anything runs.
pub fn methods(job: &ConvergenceJob) -> Result<Vec<Method>> {
    job.values
        .iter()
        .map(|v| {
            let m = Method::parse(&job.spec, &[(job.key.clone(), v.clone())])
                .map_err(|e| Error::param(format!("--values {v}: {e}")))?;
            m.check_light(job.scene)
                .map_err(|e| Error::param(format!("--values {v}: {e}")))?;
            Ok(m)
        })
        .collect()
}

pub fn run(
    ctx: &GpuContext,
    job: &ConvergenceJob,
    log: &dyn Fn(&str),
) -> Result<ConvergenceOutcome> {
    let methods = methods(job)?;
    let scene = job.scene;
    let (g, reference) = truth::for_scene(ctx, scene, job.reference, &job.cache)?;
    let judge = Judge::new(scene, &g, reference.values);
    let core = |method: &Method| RowCore {
        map_size: scene.render.shadow_map_size,
        adapter: format!("{} ({})", ctx.summary.name, ctx.summary.backend).into(),
        ..RowCore::of(&scene.name, &method.label(), method)
    };
    let mut rows = Vec::new();
    for (value, method) in job.values.iter().zip(&methods) {
        // A value that fails at run time is a row saying why, and the study goes on
        // (docs/robustness.md, "Failed settings"); before, one failure lost the whole study.
        let measured = frame::render(ctx, scene, method, TimingMode::Frame)
            .map_err(Error::from)
            .and_then(|f| {
                Ok((
                    f.output.shadow_maps,
                    judge.judge(scene, &method.label(), &f)?.metrics,
                ))
            });
        match measured {
            Ok((maps, m)) => {
                log(&format!(
                    "{}: {maps} maps, RMSE {:.5}",
                    method.label(),
                    m.rmse
                ));
                rows.push(ConvergenceRow {
                    core: RowCore {
                        maps,
                        rmse: m.rmse,
                        ..core(method)
                    },
                    value: value.clone(),
                    label: method.label(),
                    mae: m.mae,
                    failed: None,
                });
            }
            Err(e) => {
                let reason = e.to_string().replace('\n', " ");
                log(&crate::record::failed_line(
                    &format!("--values {value} ({})", method.label()),
                    &reason,
                ));
                rows.push(ConvergenceRow {
                    core: core(method),
                    value: value.clone(),
                    label: method.label(),
                    mae: 0.0,
                    failed: Some(reason),
                });
            }
        }
    }
    if let Some(line) = crate::record::failed_summary(
        rows.iter().filter(|r| r.failed.is_some()).count(),
        rows.len(),
    ) {
        log(&line);
    }
    let slope = fitted_slope(
        &rows
            .iter()
            .filter(|r| r.failed.is_none())
            .map(|r| (r.core.maps as f64, r.core.rmse))
            .collect::<Vec<_>>(),
    );
    Ok(ConvergenceOutcome {
        scene: scene.name.clone(),
        method: job.spec.clone(),
        key: job.key.clone(),
        reference: truth::mode_label(&job.reference),
        rows,
        slope,
    })
}

/// The slope of the least-squares line through (ln x, ln y), over the points with x and y > 0;
/// `None` when fewer than two distinct x remain (no line to fit).
pub fn fitted_slope(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0 && y.is_finite())
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = logs.len() as f64;
    let (mx, my) = (
        logs.iter().map(|p| p.0).sum::<f64>() / n,
        logs.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    (logs.len() >= 2 && sxx > 1e-12).then(|| sxy / sxx)
}

/// convergence.json (the outcome), convergence.csv (a row per value) and convergence.md.
pub fn files(outcome: &ConvergenceOutcome) -> Result<Vec<(String, Vec<u8>)>> {
    let json = serde_json::to_vec_pretty(outcome).map_err(|e| Error::param(e.to_string()))?;
    let any_failed = outcome.rows.iter().any(|r| r.failed.is_some());
    let mut header = RowCore::csv_header(&["value", "label", "mae"]);
    if any_failed {
        header.push("failed".into());
    }
    let mut records = vec![header];
    records.extend(outcome.rows.iter().map(|r| {
        let mut cells = r.core.cells();
        cells.extend([r.value.clone(), r.label.clone(), r.mae.to_string()]);
        if r.failed.is_some() {
            // Maps, RMSE, time and MAE were never measured.
            for i in [4, 6, 7, cells.len() - 1] {
                cells[i].clear();
            }
        }
        if any_failed {
            cells.push(r.failed.clone().unwrap_or_default());
        }
        cells
    }));
    Ok(vec![
        ("convergence.json".into(), json),
        (
            "convergence.csv".into(),
            crate::record::csv::lines(records).into_bytes(),
        ),
        ("convergence.md".into(), markdown(outcome).into_bytes()),
    ])
}

pub fn markdown(o: &ConvergenceOutcome) -> String {
    let mut md = format!("# Convergence: {} on {} against the {} reference\n\n| {} | maps | RMSE | MAE |\n|---:|---:|---:|---:|\n", o.method, o.scene, o.reference, o.key);
    for r in &o.rows {
        md += &match &r.failed {
            None => format!(
                "| {} | {} | {:.5} | {:.5} |\n",
                r.value, r.core.maps, r.core.rmse, r.mae
            ),
            Some(why) => format!(
                "| {} | failed: {} | | |\n",
                r.value,
                why.replace('|', "\\|")
            ),
        };
    }
    md += &match o.slope {
        Some(s) => {
            format!("\nFitted slope of log RMSE against log maps: {s:.3} (error ∝ maps^{s:.2}).\n")
        }
        None => {
            "\nNo slope: fewer than two distinct map counts with a non-zero error.\n".to_string()
        }
    };
    md
}

#[cfg(test)]
mod tests {
    use super::fitted_slope;

    #[test]
    fn slope_of_a_power_law_and_of_too_few_points() {
        let pts: Vec<(f64, f64)> = [4.0, 16.0, 64.0, 256.0]
            .iter()
            .map(|&x: &f64| (x, 0.3 * x.powf(-0.75)))
            .collect();
        assert!((fitted_slope(&pts).unwrap() + 0.75).abs() < 1e-12);
        assert_eq!(fitted_slope(&[(4.0, 0.1), (4.0, 0.05)]), None);
        assert_eq!(fitted_slope(&[(4.0, 0.1), (16.0, 0.0)]), None);
    }
}
