//! The table `compare` prints: the figures a reader checks first, one line per method.

use crate::methods::Family;
use crate::report::charts::ResultRow;

fn err(v: f64) -> String {
    if v != 0.0 && v.abs() < 1e-3 {
        format!("{v:.2e}")
    } else {
        format!("{v:.4}")
    }
}

pub fn render(rows: &[ResultRow]) -> String {
    let width = rows
        .iter()
        .map(|r| r.label().chars().count())
        .max()
        .unwrap_or(6)
        .max(6);
    let mut out = format!(
        "{:width$}  {:>5} {:>5}  {:>10} {:>21}  {:>9} {:>7} {:>6} {:>9} {:>9} {:>7}\n",
        "method",
        "maps",
        "syncs",
        "median ms",
        "(min-max)",
        "RMSE",
        "PSNR",
        "SSIM",
        "FLIP",
        "pen.RMSE",
        "bad"
    );
    // Grouped by family (hard, pcf family, filtered maps, multi-sample), in order within each.
    let mut rows: Vec<&ResultRow> = rows.iter().collect();
    rows.sort_by_key(|r| Family::of_name(&r.core.method));
    for r in rows {
        if let Some(reason) = &r.failed {
            out += &format!("{:width$}  failed: {reason}\n", r.label());
            continue;
        }
        let m = &r.metrics;
        out += &format!(
            "{:width$}  {:>5} {:>5}  {:>10.1} {:>21}  {:>9} {:>7} {:>6.4} {:>9.4} {:>9} {:>6.2}%\n",
            r.label(),
            r.core.maps,
            r.syncs,
            r.core.frame_ms,
            format!("({:.1}-{:.1})", r.frame_ms_min, r.frame_ms_max),
            err(m.rmse),
            m.psnr.map_or("inf".into(), |p| format!("{p:.2}")),
            m.ssim,
            m.flip_mean,
            m.penumbra_rmse.map_or("-".into(), err),
            100.0 * m.bad_pixel_share,
        );
    }
    out
}
