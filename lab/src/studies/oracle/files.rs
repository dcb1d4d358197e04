//! The oracle's output set: `oracle.csv` (a row per scene, screen, target and menu; `gain_bound`
//! a column to chart), `candidates.csv` (every candidate measured, with its price), `oracle.json`
//! (both, with each row's tile choices), `oracle.md`, `tiles/*.svg|png` (the family's choices
//! per row), `charts/gain_bound.svg|png` and a self-contained `report.html`.

use super::charts::{gain_svg, tiles_svg};
use super::{CandidateLine, OracleOutcome, OracleRow};
use crate::record::csv::lines;
use crate::report::charts::svg_to_png;
use crate::{Error, Result};

/// Header of `oracle.csv`.
pub const ROW_COLUMNS: [&str; 23] = [
    "scene",
    "resolution",
    "target",
    "menu",
    "candidates",
    "single",
    "single_rmse",
    "single_model_ms",
    "single_measured_ms",
    "oracle_ms",
    "oracle_rmse",
    "bound_ms",
    "gain_bound",
    "gain_oracle",
    "closed",
    "tiles",
    "free_tiles",
    "split",
    "not_grids",
    "best_per_tile_rmse",
    "penumbra_share",
    "tests_share",
    "gain_tests_only",
];

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or(String::new(), |x| format!("{x:.digits$}"))
}

/// `n=4@512:56(0.51)`: a class, its tiles and their penumbra share.
fn classes<'a>(cs: impl IntoIterator<Item = &'a super::Class>) -> String {
    cs.into_iter()
        .map(|c| format!("{}:{}({:.2})", c.candidate, c.tiles, c.penumbra_share))
        .collect::<Vec<_>>()
        .join(" ")
}

pub fn rows_csv(rows: &[OracleRow]) -> String {
    let mut records = vec![ROW_COLUMNS
        .iter()
        .map(|s| s.to_string())
        .collect::<Vec<_>>()];
    for r in rows {
        records.push(vec![
            r.scene.clone(),
            r.resolution.to_string(),
            r.target.to_string(),
            r.menu.clone(),
            r.candidates.to_string(),
            r.single.clone().unwrap_or_default(),
            opt(r.single_rmse, 5),
            opt(r.single_model_ms, 2),
            opt(r.single_measured_ms, 2),
            opt(r.oracle_ms, 2),
            opt(r.oracle_rmse, 5),
            opt(r.bound_ms, 2),
            opt(r.gain_bound, 3),
            opt(r.gain_oracle, 3),
            r.closed.map_or(String::new(), |c| c.to_string()),
            r.tiles.to_string(),
            r.free_tiles.to_string(),
            classes(&r.split),
            classes(r.not_grids()),
            format!("{:.5}", r.best_per_tile_rmse),
            format!("{:.4}", r.penumbra_share),
            opt(r.tests_share, 3),
            opt(r.gain_tests_only, 3),
        ]);
    }
    lines(records)
}

pub fn candidates_csv(lines_in: &[CandidateLine]) -> String {
    let mut stages: Vec<&str> = Vec::new();
    for l in lines_in {
        for k in l.stages_ms.keys() {
            if !stages.contains(&k.as_str()) {
                stages.push(k);
            }
        }
    }
    let mut head: Vec<String> = [
        "scene",
        "resolution",
        "name",
        "spec",
        "map_config",
        "kind",
        "maps",
        "rmse",
        "frame_ms",
        "frame_ms_min",
        "frame_ms_max",
        "fixed_ms",
        "maps_ms",
        "tests_ms",
        "failed",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    head.extend(stages.iter().map(|s| format!("stage_{s}_ms")));
    let mut records = vec![head];
    for l in lines_in {
        let mut r = vec![
            l.core.scene.clone(),
            l.resolution.to_string(),
            l.name.clone(),
            l.core.spec.clone(),
            l.map_config.clone(),
            l.kind.name().to_string(),
            l.core.maps.to_string(),
            format!("{:.5}", l.core.rmse),
            format!("{:.2}", l.core.frame_ms),
            format!("{:.2}", l.frame_ms_min),
            format!("{:.2}", l.frame_ms_max),
            format!("{:.3}", l.price.fixed_ms),
            format!("{:.3}", l.price.maps_ms),
            format!("{:.3}", l.price.tests_ms),
            l.failed.clone().unwrap_or_default(),
        ];
        r.extend(stages.iter().map(|s| {
            l.stages_ms
                .get(*s)
                .map_or(String::new(), |v| format!("{v:.3}"))
        }));
        records.push(r);
    }
    lines(records)
}

/// `tiles/<scene>-<resolution>-<menu>-T<target>` for a row's pictures; a scene named by its file
/// path is named by the file's stem, in letters, digits, `-` and `_`.
pub fn picture_name(r: &OracleRow) -> String {
    let stem = std::path::Path::new(&r.scene)
        .file_stem()
        .map_or(r.scene.clone(), |s| s.to_string_lossy().into_owned());
    let safe: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("tiles/{safe}-{}-{}-T{}", r.resolution, r.menu, r.target)
}

pub fn files(o: &OracleOutcome) -> Result<Vec<(String, Vec<u8>)>> {
    let json = serde_json::to_vec_pretty(&serde_json::json!({ "adapter": o.adapter, "clock": crate::record::CLOCK, "rows": o.rows, "candidates": o.candidates }))
        .map_err(|e| Error::io_text("oracle.json".into(), e.to_string()))?;
    let md = markdown(o);
    let mut out = vec![
        ("oracle.csv".to_string(), rows_csv(&o.rows).into_bytes()),
        (
            "candidates.csv".to_string(),
            candidates_csv(&o.candidates).into_bytes(),
        ),
        ("oracle.json".to_string(), json),
        ("oracle.md".to_string(), md.clone().into_bytes()),
    ];
    let mut charts: Vec<(String, String)> = Vec::new();
    if let Ok(svg) = gain_svg(&o.rows) {
        out.push(("charts/gain_bound.png".into(), svg_to_png(&svg, 1.0)?));
        out.push(("charts/gain_bound.svg".into(), svg.clone().into_bytes()));
        charts.push(("gain_bound against the target".into(), svg));
    }
    // The family's choices: where a filter, hybrid maps or a preset enters the split.
    for r in o
        .rows
        .iter()
        .filter(|r| r.menu == "family" && r.oracle_ms.is_some())
    {
        let svg = tiles_svg(r);
        let name = picture_name(r);
        out.push((format!("{name}.png"), svg_to_png(&svg, 1.0)?));
        out.push((format!("{name}.svg"), svg.clone().into_bytes()));
        charts.push((
            format!(
                "{} {}², T = {}: the family's choice per tile",
                r.scene, r.resolution, r.target
            ),
            svg,
        ));
    }
    let refs: Vec<(&str, &str)> = charts
        .iter()
        .map(|(a, b)| (a.as_str(), b.as_str()))
        .collect();
    out.push((
        "report.html".into(),
        crate::report::md_page::page(
            "The oracle: the most choosing per region could gain",
            &md,
            &refs,
        )
        .into_bytes(),
    ));
    Ok(out)
}

/// The rows as tables: per scene and screen, the bound with the grids and with the family per
/// target, then the split of each family row.
pub fn markdown(o: &OracleOutcome) -> String {
    let mut s = format!(
        "# The oracle: the most choosing per region could gain\n\n{} rows; {}; prices from each candidate's stages-mode frame scaled to its median timed frame ({}).\n\n",
        o.rows.len(),
        o.adapter,
        crate::record::CLOCK.split(';').next().unwrap_or(crate::record::CLOCK)
    );
    s += "| scene | screen | T | menu | single setting meeting T | its RMSE | its model ms | measured ms | oracle ms | bound ms | gain_bound | gain_oracle | free tiles | best per tile |\n|---|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for r in &o.rows {
        s += &format!(
            "| {} | {}² | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} of {} | {:.4} |\n",
            r.scene,
            r.resolution,
            r.target,
            r.menu,
            r.single.as_deref().unwrap_or("none"),
            opt(r.single_rmse, 4),
            opt(r.single_model_ms, 1),
            opt(r.single_measured_ms, 1),
            opt(r.oracle_ms, 1),
            opt(r.bound_ms, 1),
            opt(r.gain_bound, 2),
            opt(r.gain_oracle, 2),
            r.free_tiles,
            r.tiles,
            r.best_per_tile_rmse
        );
    }
    s += "\n## The splits\n\nEach class: the candidate, its tiles and the share of their pixels in penumbra.\n\n| scene | screen | T | menu | split | not grids |\n|---|---:|---:|---|---|---|\n";
    for r in o.rows.iter().filter(|r| !r.split.is_empty()) {
        let not = classes(r.not_grids());
        s += &format!(
            "| {} | {}² | {} | {} | {} | {} |\n",
            r.scene,
            r.resolution,
            r.target,
            r.menu,
            classes(&r.split),
            if not.is_empty() { "-".into() } else { not }
        );
    }
    s += "\n## Prices\n\nThe fixed stages every frame pays (the median over candidates of G-buffer and read-back):\n\n| scene | screen | fixed ms |\n|---|---:|---:|\n";
    for (scene, res, f) in &o.fixed_ms {
        s += &format!("| {scene} | {res}² | {f:.2} |\n");
    }
    s
}
