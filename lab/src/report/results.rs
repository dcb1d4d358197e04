//! Reports from result files: `results.jsonl` rows, the pictures they name, the charts, the
//! settings they share. `compare`, `sweep` and `penumbra report` all end here, so a report
//! re-rendered from the files equals the one the run wrote.

use std::path::{Path, PathBuf};

use super::{write_report_with_baseline, MethodImages, ReportError};
use crate::report::charts::{self, ChartError, ResultRow};
use crate::Result;

/// A row and the folder its image paths are relative to.
pub struct LoadedRow {
    pub row: ResultRow,
    pub base: PathBuf,
}

/// Reads one `results.jsonl`: one JSON object per line, blank lines skipped; any other line is
/// an error naming the file and line.
pub fn read_results(path: &Path) -> Result<Vec<LoadedRow>> {
    let err = |message: String| ReportError::Results {
        path: path.to_path_buf(),
        message,
    };
    let text = crate::scene::input_file::read_text(
        path,
        crate::scene::input_file::TEXT_CAP,
        "the 256 MiB cap on results files",
    )
    .map_err(|e| err(format!("cannot read results file: {e}")))?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    Ok(parse_results(&text, path)?
        .into_iter()
        .map(|row| LoadedRow {
            row,
            base: base.clone(),
        })
        .collect())
}

/// The rows of results.jsonl text; errors name `path` and the line.
pub fn parse_results(text: &str, path: &Path) -> Result<Vec<ResultRow>> {
    let err = |message: String| ReportError::Results {
        path: path.to_path_buf(),
        message,
    };
    let mut rows = Vec::new();
    for (n, line) in text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
    {
        let row = ResultRow::from_json(line)
            .map_err(|e| err(format!("line {}: not a result row: {e}", n + 1)))?;
        if let Some(why) = row.check() {
            return Err(err(format!("line {}: {why}", n + 1)).into());
        }
        rows.push(row);
    }
    if rows.is_empty() {
        return Err(err("no result rows".into()).into());
    }
    Ok(rows)
}

/// Every chart the rows support, as (file stem, caption, SVG); a chart with no data for these
/// rows is left out.
pub fn charts(rows: &[ResultRow]) -> Result<Vec<(&'static str, String, String)>> {
    type Chart = fn(&[ResultRow]) -> Result<String, ChartError>;
    let all: [(&str, &str, Chart); 5] = [
        (
            "error_vs_time",
            "Error against time, Pareto front marked",
            charts::error_vs_time_svg,
        ),
        (
            "error_vs_maps",
            "Error against the number of shadow maps",
            charts::error_vs_maps_svg,
        ),
        (
            "maps_vs_pm",
            "Shadow maps against P_M (adaptive)",
            charts::maps_vs_pm_svg,
        ),
        (
            "stage_breakdown",
            "Stage time breakdown",
            charts::stage_breakdown_svg,
        ),
        (
            "frame_split",
            "Frame split: raster, decision, shade, waits",
            charts::frame_split_svg,
        ),
    ];
    // Maps against P_M needs P_M to vary; one value would plot a lone point per series.
    let mut pms: Vec<f64> = rows
        .iter()
        .filter(|r| r.core.method == "adaptive")
        .filter_map(|r| r.param_f64("p_m"))
        .collect();
    pms.sort_by(f64::total_cmp);
    pms.dedup();
    let mut out = Vec::new();
    for (stem, caption, draw) in all {
        if stem == "maps_vs_pm" && pms.len() < 2 {
            continue;
        }
        match draw(rows) {
            Ok(svg) => out.push((stem, caption.to_string(), svg)),
            Err(ChartError::NoData(_)) => {}
            Err(e) => return Err(e.into()),
        }
    }
    Ok(out)
}

/// One value when all rows agree, else the distinct values joined by `; ` (first-seen order).
fn shared(rows: &[ResultRow], f: impl Fn(&ResultRow) -> String) -> String {
    let mut seen: Vec<String> = Vec::new();
    for v in rows.iter().map(f).filter(|v| !v.is_empty()) {
        if !seen.contains(&v) {
            seen.push(v);
        }
    }
    if seen.is_empty() {
        "–".into()
    } else {
        seen.join("; ")
    }
}

fn adapter_text(a: &serde_json::Value) -> String {
    let s = |k: &str| a.get(k).and_then(|v| v.as_str()).unwrap_or("").to_string();
    match a {
        serde_json::Value::Object(_) => {
            let driver = [s("driver"), s("driver_info")].join(" ").trim().to_string();
            format!(
                "{} ({}, {}{})",
                s("name"),
                s("backend"),
                s("device_type"),
                if driver.is_empty() {
                    String::new()
                } else {
                    format!(", {driver}")
                }
            )
        }
        serde_json::Value::String(x) => x.clone(),
        _ => String::new(),
    }
}

/// The shards the rows came from, with the rows each gave: `0/4 (6 rows), 1/4 (6 rows)`.
fn shard_list(rows: &[ResultRow]) -> String {
    let mut shards: Vec<([u32; 2], usize)> = Vec::new();
    for s in rows
        .iter()
        .filter_map(|r| r.provenance.as_ref()?.spec.as_ref())
    {
        match shards.iter_mut().find(|(k, _)| *k == s.shard) {
            Some((_, n)) => *n += 1,
            None => shards.push((s.shard, 1)),
        }
    }
    shards.sort();
    if shards.is_empty() {
        "–".into()
    } else {
        shards
            .iter()
            .map(|([i, n], c)| format!("{i}/{n} ({c} rows)"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The settings table of the report, from what the rows record, as ordered `[key, value]` pairs.
pub fn settings(rows: &[ResultRow]) -> serde_json::Value {
    let version = |r: &ResultRow| match &r.core.version {
        serde_json::Value::Object(v) => format!(
            "penumbra {} (git {})",
            v.get("crate").and_then(|x| x.as_str()).unwrap_or("?"),
            v.get("git").and_then(|x| x.as_str()).unwrap_or("?")
        ),
        _ => String::new(),
    };
    let pairs = [
        ("scene", shared(rows, |r| r.core.scene.clone())),
        ("adapter", shared(rows, |r| adapter_text(&r.core.adapter))),
        ("resolution", shared(rows, |r| r.resolution.map(|[w, h]| format!("{w}x{h}")).unwrap_or_default())),
        ("shadow map size", shared(rows, |r| Some(r.core.map_size).filter(|s| *s > 0).map(|s| format!("{s}x{s}")).unwrap_or_default())),
        ("shadow-map raster", shared(rows, |r| r.raster.clone().unwrap_or_default())),
        ("reference", shared(rows, |r| r.reference.clone())),
        (
            "timing",
            shared(rows, |r| if r.repeats > 0 { format!("one warm-up frame, then the median of {} frames; methods interleaved round by round in windows of {}", r.repeats, crate::record::measure::WINDOW) } else { String::new() }),
        ),
        ("clock", shared(rows, |r| r.clock.clone())),
        ("metrics", "geometry pixels only; FLIP on the shaded images; definitions in docs/compare-and-report.md".into()),
        ("version", shared(rows, version)),
        ("scene files", shared(rows, |r| r.provenance.as_ref().map(|p| format!("{} (sha256 {:.12})", p.scene_file, p.scene_sha256)).unwrap_or_default())),
        ("meshes", shared(rows, |r| r.provenance.as_ref().map(|p| p.meshes.iter().map(|m| format!("{} (sha256 {:.12})", m.file, m.sha256)).collect::<Vec<_>>().join(", ")).unwrap_or_default())),
        ("overrides", shared(rows, |r| r.provenance.as_ref().map(|p| p.overrides.join(" ")).unwrap_or_default())),
        ("produced by", shared(rows, |r| r.provenance.as_ref().map(|p| p.command.clone()).unwrap_or_default())),
        ("sweep spec", shared(rows, |r| r.provenance.as_ref().and_then(|p| p.spec.as_ref()).map(|s| format!("{} (sha256 {:.12}, {} configurations)", s.file, s.sha256, s.configs)).unwrap_or_default())),
        ("shards", shard_list(rows)),
        ("rows", rows.len().to_string()),
    ];
    serde_json::Value::Array(
        pairs
            .into_iter()
            .map(|(k, v)| serde_json::json!([k, v]))
            .collect(),
    )
}

/// The pictures of a row, read from the files it names; `None` when it names none (a row from
/// elsewhere). A named file that is missing is an error.
fn images(r: &LoadedRow) -> Result<Option<MethodImages>> {
    let read = |key: &str| -> Result<Option<Vec<u8>>> {
        let Some(rel) = r.row.images.get(key) else {
            return Ok(None);
        };
        let path = r.base.join(rel);
        let bytes = crate::scene::input_file::read_capped(
            &path,
            crate::scene::input_file::TEXT_CAP,
            "the 256 MiB cap on pictures",
        )
        .map_err(|e| ReportError::Results {
            path: path.clone(),
            message: format!("image `{key}` of {}: {e}", r.row.label()),
        })?;
        Ok(Some(bytes))
    };
    let (Some(shaded_png), Some(visibility_png), Some(abs_error_png), Some(reference_png)) = (
        read("shaded")?,
        read("visibility")?,
        read("abs_error")?,
        read("reference")?,
    ) else {
        return Ok(None);
    };
    Ok(Some(MethodImages {
        label: r.row.label(),
        scene: r.row.core.scene.clone(),
        shaded_png,
        visibility_png,
        abs_error_png,
        reference_png,
        signed_error_png: read("signed_error")?,
    }))
}

/// Writes `report.html`, `report.md` and `report_files/` for these rows into `out_dir`;
/// returns the path of `report.html`.
pub fn write_from_rows(rows: &[LoadedRow], out_dir: &Path) -> Result<PathBuf> {
    write_rows(rows, None, out_dir)
}

fn write_rows(
    rows: &[LoadedRow],
    baseline: Option<&[ResultRow]>,
    out_dir: &Path,
) -> Result<PathBuf> {
    let plain: Vec<ResultRow> = rows.iter().map(|r| r.row.clone()).collect();
    let title = format!(
        "Penumbra: speed against accuracy, {}",
        super::table::scenes(plain.iter().map(|r| r.core.scene.as_str())).join(", ")
    );
    let mut pictures = Vec::new();
    for r in rows {
        pictures.extend(images(r)?);
    }
    let measured: Vec<ResultRow> = plain.iter().filter(|r| r.measured()).cloned().collect();
    let charts: Vec<(String, String)> = charts(&measured)?
        .into_iter()
        .map(|(_, caption, svg)| (caption, svg))
        .collect();
    let mut settings = settings(&plain);
    if let (Some(b), serde_json::Value::Array(pairs)) = (baseline, &mut settings) {
        pairs.push(serde_json::json!([
            "baseline",
            format!(
                "{} rows; changes in the tables marked \"against the baseline\"",
                b.len()
            )
        ]));
    }
    write_report_with_baseline(
        out_dir, &title, &settings, &plain, &pictures, &charts, baseline,
    )?;
    Ok(out_dir.join("report.html"))
}

/// `penumbra report FILES… --out DIR`: every file is read before anything is written.
pub fn write_from_files(paths: &[PathBuf], out_dir: &Path) -> Result<PathBuf> {
    write_from_files_with_baseline(paths, None, out_dir)
}

/// As [`write_from_files`], with the change of every row against a baseline results file.
pub fn write_from_files_with_baseline(
    paths: &[PathBuf],
    baseline: Option<&Path>,
    out_dir: &Path,
) -> Result<PathBuf> {
    if paths.is_empty() {
        return Err(crate::Error::param(
            "report: give at least one results.jsonl".into(),
        ));
    }
    let mut seen = Vec::new();
    for p in paths {
        // The same file twice would double every row in the tables and charts.
        let id = p.canonicalize().unwrap_or_else(|_| p.clone());
        if seen.contains(&id) {
            return Err(crate::Error::param(format!(
                "report: {} is given twice",
                p.display()
            )));
        }
        seen.push(id);
    }
    let mut rows = Vec::new();
    for p in paths {
        rows.extend(read_results(p)?);
    }
    let old = match baseline {
        Some(b) => Some(
            read_results(b)?
                .into_iter()
                .map(|l| l.row)
                .collect::<Vec<_>>(),
        ),
        None => None,
    };
    write_rows(&rows, old.as_deref(), out_dir)
}
