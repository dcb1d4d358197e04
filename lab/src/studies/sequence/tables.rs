//! The sequence's text tables: CSV of frames and of per-method summaries, and the summary as a
//! plain-text table for the terminal.

use super::{FrameRow, MethodSummary};
use crate::record::RowCore;

/// A CSV field, quoted as in results.csv when it holds a comma or a quote.
fn field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

pub fn frames_csv(rows: &[FrameRow]) -> String {
    let own = [
        "label",
        "frame",
        "mae",
        "max_abs",
        "bad_pixel_share",
        "flip_mean",
        "temporal_rmse",
        "popping_share",
        "popping_pixels",
        "temporal_pixels",
        "reuse",
        "maps_rendered",
        "maps_kept",
        "maps_redrawn",
        "texels_rasterized",
        "texels_used",
        "v_equal_without_reuse",
        "kept_bytes",
    ];
    let header = RowCore::csv_header(&own);
    let cells = rows.iter().map(|r| {
        let t = r.temporal;
        let opt = |v: Option<String>| v.unwrap_or_default();
        let mut c = r.core.cells();
        c.extend([
            r.label.clone(),
            r.frame.to_string(),
            format!("{:.6}", r.metrics.mae),
            format!("{:.6}", r.metrics.max_abs),
            format!("{:.6}", r.metrics.bad_pixel_share),
            format!("{:.6}", r.metrics.flip_mean),
            opt(t.map(|t| format!("{:.6}", t.temporal_rmse))),
            opt(t.map(|t| format!("{:.6}", t.popping_share))),
            opt(t.map(|t| t.popping_pixels.to_string())),
            opt(t.map(|t| t.pixels.to_string())),
            r.reuse.to_string(),
            r.reuse_counts.rendered.to_string(),
            r.reuse_counts.kept.to_string(),
            r.reuse_counts.redrawn.to_string(),
            r.reuse_counts.texels.to_string(),
            r.reuse_counts.texels_used.to_string(),
            opt(r.v_equal_without_reuse.map(|e| e.to_string())),
            r.kept_bytes.to_string(),
        ]);
        c
    });
    crate::record::csv::lines(std::iter::once(header).chain(cells))
}

pub fn summary_csv(rows: &[MethodSummary]) -> String {
    let mut s = String::from(
        "label,frames,mean_rmse,mean_bad_pixel_share,temporal_rmse,popping_share,popping_pixels,maps_mean,maps_min,maps_max,median_ms,reuse,mean_ms_after_first,rendered_mean_after_first,kept_mean_after_first,texel_share_after_first,v_equal_frames,v_compared_frames,time_ratio_to_without_reuse,median_ms_after_first,kept_bytes_max\n",
    );
    for m in rows {
        s += &format!(
            "{},{},{:.6},{:.6},{:.6},{:.6},{},{:.2},{},{},{:.3},{},{:.3},{:.2},{:.2},{:.6},{},{},{},{:.3},{}\n",
            field(&m.label),
            m.frames,
            m.mean_rmse,
            m.mean_bad_pixel_share,
            m.temporal.temporal_rmse,
            m.temporal.popping_share,
            m.temporal.popping_pixels,
            m.maps_mean,
            m.maps_min,
            m.maps_max,
            m.median_ms,
            m.reuse,
            m.mean_ms_after_first,
            m.rendered_mean_after_first,
            m.kept_mean_after_first,
            m.texel_share_after_first,
            m.v_equal_frames.map_or(String::new(), |v| v.0.to_string()),
            m.v_equal_frames.map_or(String::new(), |v| v.1.to_string()),
            m.time_ratio_to_without_reuse.map_or(String::new(), |r| format!("{r:.4}")),
            m.median_ms_after_first,
            m.kept_bytes_max,
        );
    }
    s
}

/// The per-method figures as a plain-text table for the terminal.
pub fn summary_table(rows: &[MethodSummary]) -> String {
    let mut s = format!(
        "{:<28} {:>10} {:>13} {:>10} {:>8} {:>16} {:>10} {:>14} {:>12} {:>9} {:>12}\n",
        "method",
        "mean RMSE",
        "temporal RMSE",
        "popping %",
        "pops",
        "maps per frame",
        "median ms",
        "mean ms (1..)",
        "rendered (1..)",
        "V equal",
        "time ratio"
    );
    for m in rows {
        let maps = if m.maps_min == m.maps_max {
            m.maps_min.to_string()
        } else {
            format!("{:.1} ({}-{})", m.maps_mean, m.maps_min, m.maps_max)
        };
        let equal = m
            .v_equal_frames
            .map_or("-".to_string(), |(e, n)| format!("{e}/{n}"));
        let ratio = m
            .time_ratio_to_without_reuse
            .map_or("-".to_string(), |r| format!("{r:.3}"));
        s += &format!(
            "{:<28} {:>10.4} {:>13.4} {:>10.3} {:>8} {:>16} {:>10.1} {:>14.1} {:>12.1} {:>9} {:>12}\n",
            m.label,
            m.mean_rmse,
            m.temporal.temporal_rmse,
            100.0 * m.temporal.popping_share,
            m.temporal.popping_pixels,
            maps,
            m.median_ms,
            m.mean_ms_after_first,
            m.rendered_mean_after_first,
            equal,
            ratio
        );
    }
    s
}
