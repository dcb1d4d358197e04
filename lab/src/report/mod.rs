//! The report: one self-contained `report.html` (no external resource of any kind) and a
//! `report.md` whose images live in `report_files/` beside it.

mod baseline;
pub mod charts;
mod dominance;
mod files;
mod html;
mod markdown;
pub mod md_page;
pub(crate) mod page;
pub mod results;
pub mod results_folder;
pub mod results_index;
mod table;
pub mod viewer;

use std::path::{Path, PathBuf};

use crate::report::charts::ResultRow;
pub(crate) use files::unique_slugs;
use files::{data_uri, is_png, write_atomic};

/// Folder, beside `report.md`, holding the files the Markdown links to.
pub const FILES_DIR: &str = "report_files";

/// The pictures of one method, all PNG-encoded.
#[derive(Debug, Clone)]
pub struct MethodImages {
    /// Usually `ResultRow::label()`.
    pub label: String,
    /// The row's scene: with the label, it finds the row whose figures the viewer shows.
    pub scene: String,
    pub shaded_png: Vec<u8>,
    pub visibility_png: Vec<u8>,
    pub abs_error_png: Vec<u8>,
    /// The shaded reference this method is compared with.
    pub reference_png: Vec<u8>,
    /// Signed error of V (blue: too dark, red: too bright), when available.
    pub signed_error_png: Option<Vec<u8>>,
}

#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error("{which} image of {label:?} is not a PNG")]
    NotPng { label: String, which: &'static str },
    #[error("chart {0:?} is not an SVG document")]
    NotSvg(String),
    #[error("template: {0}")]
    Template(#[from] minijinja::Error),
    /// A results file is missing, unreadable or has a malformed line.
    #[error("{path}: {message}")]
    Results { path: PathBuf, message: String },
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

/// Writes `report.html`, `report.md` and `report_files/*` into `out_dir` (created if missing).
/// Everything is rendered in memory first and each file is written atomically, images before
/// the pages that reference them, so an error never leaves a partial file.
pub fn write_report(
    out_dir: &Path,
    title: &str,
    settings: &serde_json::Value,
    rows: &[ResultRow],
    images: &[MethodImages],
    charts: &[(String, String)],
) -> Result<(), ReportError> {
    write_report_with_baseline(out_dir, title, settings, rows, images, charts, None)
}

/// As [`write_report`], with a table per scene of each row's change against `baseline` rows.
pub fn write_report_with_baseline(
    out_dir: &Path,
    title: &str,
    settings: &serde_json::Value,
    rows: &[ResultRow],
    images: &[MethodImages],
    charts: &[(String, String)],
    baseline: Option<&[ResultRow]>,
) -> Result<(), ReportError> {
    for m in images {
        let parts = [
            ("shaded", &m.shaded_png),
            ("visibility", &m.visibility_png),
            ("abs error", &m.abs_error_png),
            ("reference", &m.reference_png),
        ];
        let signed = m.signed_error_png.iter().map(|b| ("signed error", b));
        if let Some((which, _)) = parts.into_iter().chain(signed).find(|(_, b)| !is_png(b)) {
            return Err(ReportError::NotPng {
                label: m.label.clone(),
                which,
            });
        }
    }
    if let Some((name, _)) = charts
        .iter()
        .find(|(_, svg)| !svg.trim_start().starts_with("<svg"))
    {
        return Err(ReportError::NotSvg(name.clone()));
    }

    let settings = table::settings_pairs(settings);
    // Failed settings get their own table ("failed: reason"); every other table is of measured rows.
    let all = rows;
    let rows: &[ResultRow] = &all
        .iter()
        .filter(|r| r.measured())
        .cloned()
        .collect::<Vec<_>>();
    let mut tables = table::tables(rows);
    tables.extend(table::failed_tables(all));
    tables.extend(table::certified_tables(all));
    tables.extend(dominance::tables(rows));
    if let Some(old) = baseline {
        let old: Vec<ResultRow> = old.iter().filter(|r| r.measured()).cloned().collect();
        tables.extend(baseline::tables(&old, rows));
    }
    // (relative path, bytes) of every file the Markdown links to.
    let mut assets: Vec<(String, Vec<u8>)> = Vec::new();

    let chart_slugs = unique_slugs(charts.iter().map(|(n, _)| n.as_str()));
    let mut chart_views = Vec::new();
    let mut chart_links = Vec::new();
    for ((name, svg), slug) in charts.iter().zip(&chart_slugs) {
        let path = format!("{FILES_DIR}/chart_{slug}.svg");
        chart_views.push(html::ChartView {
            name: name.clone(),
            svg: html::inline_svg(svg),
        });
        chart_links.push(markdown::Link {
            caption: name.clone(),
            path: path.clone(),
        });
        assets.push((path, svg.as_bytes().to_vec()));
    }

    let method_slugs = unique_slugs(images.iter().map(|m| m.label.as_str()));
    let mut method_links = Vec::new();
    for (m, slug) in images.iter().zip(&method_slugs) {
        let parts = [
            ("reference", "reference (shaded)", &m.reference_png),
            ("shaded", "shaded", &m.shaded_png),
            ("visibility", "visibility V", &m.visibility_png),
            ("abs_error", "|error| of V", &m.abs_error_png),
        ];
        let signed = m
            .signed_error_png
            .iter()
            .map(|b| ("signed_error", "signed error of V", b));
        let mut links = Vec::new();
        for (suffix, caption, bytes) in parts.into_iter().chain(signed) {
            // Methods usually share one reference: write identical bytes once.
            let existing = (suffix == "reference")
                .then(|| {
                    assets
                        .iter()
                        .find(|(p, b)| p.ends_with("_reference.png") && b == bytes)
                })
                .flatten()
                .map(|(p, _)| p.clone());
            let path = existing.unwrap_or_else(|| {
                let p = format!("{FILES_DIR}/{slug}_{suffix}.png");
                assets.push((p.clone(), bytes.clone()));
                p
            });
            links.push(markdown::Link {
                caption: caption.into(),
                path,
            });
        }
        method_links.push(markdown::MethodLinks {
            label: m.label.clone(),
            tiles: links,
        });
    }
    let viewers = viewers(images, rows)?;

    let page = html::Page {
        title,
        settings: settings.clone(),
        tables: &tables,
        charts: chart_views,
        viewers,
        viewer_head: viewer::HEAD,
    };
    let html = html::render(&page)?;
    let md = markdown::render(title, &settings, &tables, &chart_links, &method_links);

    let mkdir = |p: PathBuf| {
        std::fs::create_dir_all(&p).map_err(|source| ReportError::Io { path: p, source })
    };
    mkdir(out_dir.join(FILES_DIR))?;
    for (rel, bytes) in &assets {
        write_atomic(&out_dir.join(rel), bytes)?;
    }
    write_atomic(&out_dir.join("report.md"), md.as_bytes())?;
    write_atomic(&out_dir.join("report.html"), html.as_bytes())
}

/// One viewer per reference the methods were compared with (a scene's, in practice): the
/// reference once, then each method with its pictures and its row's RMSE, FLIP, maps and time.
fn viewers(images: &[MethodImages], rows: &[ResultRow]) -> Result<Vec<String>, ReportError> {
    let mut groups: Vec<(&[u8], Vec<&MethodImages>)> = Vec::new();
    for m in images {
        match groups
            .iter_mut()
            .find(|(r, _)| *r == m.reference_png.as_slice())
        {
            Some((_, g)) => g.push(m),
            None => groups.push((&m.reference_png, vec![m])),
        }
    }
    let png = |name: &str, caption: &str, bytes: &[u8]| viewer::Layer {
        name: name.into(),
        caption: caption.into(),
        uri: data_uri("image/png", bytes),
    };
    let mut out = Vec::new();
    for (reference, methods) in groups {
        let scene = methods[0].scene.clone();
        let mut items = vec![viewer::Item {
            label: "reference".into(),
            reference: true,
            figures: String::new(),
            layers: vec![png("shaded", "reference (shaded)", reference)],
        }];
        for m in methods {
            let row = rows
                .iter()
                .find(|r| r.core.scene == m.scene && r.label() == m.label);
            let mut layers = vec![
                png("shaded", "shaded", &m.shaded_png),
                png("visibility", "visibility V", &m.visibility_png),
                png("abs_error", "|error| of V", &m.abs_error_png),
            ];
            layers.extend(
                m.signed_error_png
                    .as_deref()
                    .map(|b| png("signed_error", "signed error of V", b)),
            );
            items.push(viewer::Item {
                label: m.label.clone(),
                reference: false,
                figures: row.map(figures).unwrap_or_default(),
                layers,
            });
        }
        let title = format!("images of {scene}: the reference and every method");
        out.push(viewer::render(&viewer::Viewer {
            title,
            scene,
            items,
        })?);
    }
    Ok(out)
}

/// The figures beside a method in the viewer: what the tables say of it, on one line.
fn figures(r: &ResultRow) -> String {
    let maps = if r.core.maps == 1 {
        "1 map".to_string()
    } else {
        format!("{} maps", r.core.maps)
    };
    format!(
        "RMSE {:.4} · FLIP {:.4} · {maps} · {:.2} ms",
        r.metrics.rmse, r.metrics.flip_mean, r.core.frame_ms
    )
}

#[cfg(test)]
mod tests;
