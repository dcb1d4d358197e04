//! The cascade study's output set: `cascades.jsonl` (one line per setting), `cascades.csv` (one
//! row per cascade), `cascades.md`, `charts/cascades.svg`/`.png` and a self-contained `report.html`.

use super::charts::{cascades_svg, CascadePoint};
use super::CascadeLine;
use crate::record::RowCore;
use crate::report::charts::svg_to_png;
use crate::{Error, Result};

pub fn files(lines: &[CascadeLine]) -> Result<Vec<(String, Vec<u8>)>> {
    let mut jsonl = String::new();
    for l in lines {
        jsonl += &serde_json::to_string(l)
            .map_err(|e| Error::io_text("cascades.jsonl".into(), e.to_string()))?;
        jsonl.push('\n');
    }
    let scene = lines.first().map_or("", |l| l.core.scene.as_str());
    let points: Vec<CascadePoint> = lines
        .iter()
        .map(|l| CascadePoint {
            scheme: l.scheme(),
            n: l.n,
            rmse: l.core.rmse,
        })
        .collect();
    let svg = cascades_svg(scene, &points)?;
    let md = markdown(lines);
    let html = crate::report::md_page::page(
        &format!("Cascades: {scene}"),
        &md,
        &[("Error against the number of cascades", &svg)],
    );
    Ok(vec![
        ("cascades.jsonl".to_string(), jsonl.into_bytes()),
        ("cascades.csv".to_string(), csv(lines).into_bytes()),
        ("cascades.md".to_string(), md.into_bytes()),
        ("charts/cascades.png".to_string(), svg_to_png(&svg, 1.0)?),
        ("charts/cascades.svg".to_string(), svg.into_bytes()),
        ("report.html".to_string(), html.into_bytes()),
    ])
}

fn density(d: Option<f64>) -> String {
    d.map_or("-".into(), |d| format!("{d:.2}"))
}

/// One row per cascade of every setting.
pub fn csv(lines: &[CascadeLine]) -> String {
    let own = [
        "split",
        "lambda",
        "filter",
        "n",
        "cascade",
        "near",
        "far",
        "texel_world",
        "pixels",
        "share",
        "density_median",
    ];
    let header = RowCore::csv_header(&own);
    let mut rows = vec![header];
    for l in lines {
        for c in &l.cascades {
            let mut r = l.core.cells();
            r.extend([
                l.split.clone(),
                l.lambda.to_string(),
                l.filter.clone(),
                l.n.to_string(),
                c.index.to_string(),
                format!("{:.4}", c.near),
                format!("{:.4}", c.far),
                format!("{:.6}", c.texel_world),
                c.pixels.to_string(),
                format!("{:.6}", c.share),
                c.density_median
                    .map_or(String::new(), |d| format!("{d:.4}")),
            ]);
            rows.push(r);
        }
    }
    crate::record::csv::lines(rows)
}

/// The error table (schemes against n), then each setting's cascades.
pub fn markdown(lines: &[CascadeLine]) -> String {
    let Some(first) = lines.first() else {
        return "# Cascades\n\nNo settings.\n".into();
    };
    let mut s = format!(
        "# Cascades: {}\n\n{}x{} screen, {}² maps, filter `{}`; reference {}; {}.\n\n",
        first.core.scene,
        first.resolution[0],
        first.resolution[1],
        first.core.map_size,
        first.filter,
        first.reference,
        first.core.adapter
    );
    let mut ns: Vec<u32> = lines.iter().map(|l| l.n).collect();
    ns.sort();
    ns.dedup();
    let mut schemes: Vec<String> = lines.iter().map(CascadeLine::scheme).collect();
    schemes.dedup();
    s += "## RMSE of V over geometry pixels\n\n| split |";
    for n in &ns {
        s += &format!(" n = {n} |");
    }
    s += "\n|---|";
    s += &"---:|".repeat(ns.len());
    s += "\n";
    for scheme in &schemes {
        s += &format!("| {scheme} |");
        for n in &ns {
            let cell = lines
                .iter()
                .find(|l| &l.scheme() == scheme && l.n == *n)
                .map_or("-".into(), |l| format!("{:.5}", l.core.rmse));
            s += &format!(" {cell} |");
        }
        s += "\n";
    }
    s += "\n## Each cascade: its slice, texel and density on screen\n\n\
          Density: screen pixels one texel spans across the view, the median over the pixels the cascade serves.\n\n\
          | split | n | cascade | view depth | texel (world) | share of pixels | density (px/texel) |\n|---|---:|---:|---|---:|---:|---:|\n";
    for l in lines {
        for c in &l.cascades {
            s += &format!(
                "| {} | {} | {} | {:.1}–{:.1} | {:.4} | {:.3} | {} |\n",
                l.scheme(),
                l.n,
                c.index,
                c.near,
                c.far,
                c.texel_world,
                c.share,
                density(c.density_median)
            );
        }
    }
    s
}
