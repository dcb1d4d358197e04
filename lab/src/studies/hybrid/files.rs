//! The hybrid study's files: rows as JSONL and CSV, Markdown tables (what docs/bench.md quotes),
//! the error-against-memory chart and a self-contained HTML page.

use super::charts::{error_memory_svg, MemoryPoint};
use super::HybridRow;
use crate::record::RowCore;
use crate::report::charts::svg_to_png;
use crate::{Error, Result};

fn io_error(what: &str, e: impl std::fmt::Display) -> Error {
    Error::io_text(what.into(), e.to_string())
}

pub fn files(rows: &[HybridRow]) -> Result<Vec<(String, Vec<u8>)>> {
    let mut files = Vec::new();
    let mut jsonl = String::new();
    for r in rows {
        jsonl += &serde_json::to_string(r).map_err(|e| io_error("hybrid.jsonl", e))?;
        jsonl.push('\n');
    }
    files.push(("hybrid.jsonl".to_string(), jsonl.into_bytes()));
    files.push(("hybrid.csv".to_string(), csv(rows).into_bytes()));
    let md = markdown(rows);
    let mut svg = None;
    let points: Vec<MemoryPoint> = rows
        .iter()
        .filter(|r| r.part == "hard")
        .map(|r| MemoryPoint {
            series: if r.kind == "plain" {
                "plain".into()
            } else {
                format!("hybrid, {} level(s)", r.levels)
            },
            label: r.map_config.clone(),
            bytes_per_map: r.bytes_per_map,
            mismatch_share: r.mismatch_share,
        })
        .collect();
    if !points.is_empty() {
        let chart = error_memory_svg(&points)?;
        files.push((
            "charts/error_memory.png".to_string(),
            svg_to_png(&chart, 1.0)?,
        ));
        files.push((
            "charts/error_memory.svg".to_string(),
            chart.clone().into_bytes(),
        ));
        svg = Some(chart);
    }
    let charts: Vec<(&str, &str)> = svg
        .iter()
        .map(|c| ("Error against memory", c.as_str()))
        .collect();
    files.push((
        "report.html".to_string(),
        crate::report::md_page::page("Hybrid-resolution shadow maps", &md, &charts).into_bytes(),
    ));
    files.push(("hybrid.md".to_string(), md.into_bytes()));
    Ok(files)
}

fn csv(rows: &[HybridRow]) -> String {
    let own = [
        "part",
        "label",
        "map_config",
        "kind",
        "levels",
        "bytes_per_map",
        "share_of_plain",
        "reference",
        "mismatch_share",
        "syncs",
        "frame_ms_min",
        "frame_ms_max",
        "raster_ms",
        "build_ms",
        "lookup_ms",
        "resolution",
    ];
    let header = RowCore::csv_header(&own);
    let cells = rows.iter().map(|r| {
        let mut c = r.core.cells();
        c.extend([
            r.part.clone(),
            r.label.clone(),
            r.map_config.clone(),
            r.kind.clone(),
            r.levels.to_string(),
            format!("{:.0}", r.bytes_per_map),
            format!("{:.6}", r.share_of_plain),
            r.reference.clone(),
            format!("{:.6}", r.mismatch_share),
            r.syncs.to_string(),
            format!("{:.3}", r.frame_ms_min),
            format!("{:.3}", r.frame_ms_max),
            format!("{:.3}", r.raster_ms),
            format!("{:.3}", r.build_ms),
            format!("{:.3}", r.lookup_ms),
            r.resolution.to_string(),
        ]);
        c
    });
    crate::record::csv::lines(std::iter::once(header).chain(cells))
}

fn mib(bytes: f64) -> String {
    format!("{:.3}", bytes / 1048576.0)
}

/// Hard-shadow table, the seed's time claim (hybrid against plain of the same raster size), and
/// the multi-map table.
pub fn markdown(rows: &[HybridRow]) -> String {
    let mut s = String::from("# Hybrid-resolution shadow maps (seed 003)\n");
    let hard: Vec<&HybridRow> = rows.iter().filter(|r| r.part == "hard").collect();
    if let Some(first) = hard.first() {
        s += &format!(
            "\n## Hard shadows on {} ({}², reference: {}; times: {} on {})\n\n\
             | maps | MiB per map | of plain at its raster size | mismatched pixels | median ms | raster ms | build ms | lookup ms |\n|---|---:|---:|---:|---:|---:|---:|---:|\n",
            first.core.scene, first.resolution, first.reference, first.clock, first.core.adapter.as_str().unwrap_or_default()
        );
        for r in &hard {
            s += &format!(
                "| {} | {} | {:.1}% | {:.3}% | {:.1} | {:.1} | {:.1} | {:.1} |\n",
                r.map_config,
                mib(r.bytes_per_map),
                100.0 * r.share_of_plain,
                100.0 * r.mismatch_share,
                r.core.frame_ms,
                r.raster_ms,
                r.build_ms,
                r.lookup_ms
            );
        }
        let pairs: Vec<(&&HybridRow, &&HybridRow)> = hard
            .iter()
            .filter(|r| r.kind == "hybrid")
            .filter_map(|h| {
                hard.iter()
                    .find(|p| p.kind == "plain" && p.core.map_size == h.core.map_size)
                    .map(|p| (h, p))
            })
            .collect();
        if !pairs.is_empty() {
            s += "\nTime of a hybrid map against the plain map of its raster size (the seed claims 5-12% less):\n\n\
                  | hybrid | plain | frame time change | raster + lookup change | build share of the hybrid frame |\n|---|---|---:|---:|---:|\n";
            for (h, p) in pairs {
                s += &format!(
                    "| {} | {} | {:+.1}% | {:+.1}% | {:.1}% |\n",
                    h.map_config,
                    p.map_config,
                    100.0 * (h.core.frame_ms / p.core.frame_ms - 1.0),
                    100.0 * ((h.raster_ms + h.lookup_ms) / (p.raster_ms + p.lookup_ms) - 1.0),
                    100.0 * h.build_ms / (h.raster_ms + h.build_ms + h.lookup_ms).max(1e-9)
                );
            }
        }
    }
    let multi: Vec<&HybridRow> = rows.iter().filter(|r| r.part == "multi").collect();
    if let Some(first) = multi.first() {
        s += &format!(
            "\n## Multi-map methods on {} ({}², reference: {})\n\n\
             | method | maps | MiB per map | RMSE | median ms | raster ms | build ms | lookup ms | store peak MiB | flushes |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
            first.core.scene, first.resolution, first.reference
        );
        for r in &multi {
            let peak = r.store["store_peak_bytes"]
                .as_f64()
                .map_or("-".to_string(), mib);
            let flushes = r.store["flushes"]
                .as_u64()
                .map_or("-".to_string(), |f| f.to_string());
            s += &format!(
                "| {} | {} | {} | {:.5} | {:.0} | {:.0} | {:.0} | {:.0} | {} | {} |\n",
                r.label,
                r.map_config,
                mib(r.bytes_per_map),
                r.core.rmse,
                r.core.frame_ms,
                r.raster_ms,
                r.build_ms,
                r.lookup_ms,
                peak,
                flushes
            );
        }
    }
    s
}
