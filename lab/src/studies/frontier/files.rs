//! The frontier's output set: `frontier.jsonl` (one line per setting), `frontier.md` (the
//! tables), `charts/frontier.svg`/`.png` and a self-contained `report.html`.

use super::charts::{frontier_svg, FrontierPoint};
use super::{front, FrontierLine};
use crate::report::charts::svg_to_png;
use crate::{Error, Result};

pub fn files(lines: &[FrontierLine]) -> Result<Vec<(String, Vec<u8>)>> {
    let mut jsonl = String::new();
    for l in lines {
        jsonl += &serde_json::to_string(l)
            .map_err(|e| Error::io_text("frontier.jsonl".into(), e.to_string()))?;
        jsonl.push('\n');
    }
    let scene = lines.first().map_or("", |l| l.core.scene.as_str());
    let points: Vec<FrontierPoint> = lines
        .iter()
        .filter(|l| l.failed.is_none())
        .map(|l| FrontierPoint {
            kind: if l.map_config.starts_with("hybrid") {
                format!("{}, hybrid maps", l.kind)
            } else {
                l.kind.clone()
            },
            label: format!("{} @{}", l.core.spec, short_maps(&l.map_config)),
            ms: l.core.frame_ms,
            ms_span: (l.frame_ms_min, l.frame_ms_max),
            rmse: l.core.rmse,
            on_frontier: l.on_frontier,
        })
        .collect();
    let svg = frontier_svg(scene, &points)?;
    let md = markdown(lines);
    let budget: Vec<&FrontierLine> = lines
        .iter()
        .filter(|l| l.is_budget() && l.failed.is_none())
        .collect();
    let calibration = super::budget::chart(&budget);
    let mut charts = vec![("Error against time", svg.as_str())];
    if let Some(c) = &calibration {
        charts.push(("The error budget: predicted against measured", c.as_str()));
    }
    let html = crate::report::md_page::page(
        &format!("Frontier of fixed settings: {scene}"),
        &md,
        &charts,
    );
    let mut out = vec![
        ("frontier.jsonl".to_string(), jsonl.into_bytes()),
        ("frontier.md".to_string(), md.into_bytes()),
        ("charts/frontier.png".to_string(), svg_to_png(&svg, 1.0)?),
        ("charts/frontier.svg".to_string(), svg.into_bytes()),
        ("report.html".to_string(), html.into_bytes()),
    ];
    if let Some(c) = calibration {
        out.push(("charts/calibration.png".to_string(), svg_to_png(&c, 1.0)?));
        out.push(("charts/calibration.svg".to_string(), c.into_bytes()));
    }
    Ok(out)
}

/// `plain 512` → `512`, `hybrid 2048→512` → `h2048→512`: chart labels stay short.
fn short_maps(config: &str) -> String {
    config
        .strip_prefix("plain ")
        .map(str::to_string)
        .unwrap_or_else(|| config.replace("hybrid ", "h"))
}

fn flip(l: &FrontierLine) -> String {
    l.flip.map_or("-".into(), |f| format!("{f:.4}"))
}

/// Which raster drew each map configuration's maps (`raster = auto` may pick per map size), as
/// one line: `Shadow-map raster: compute (plain 512, plain 1024); hardware (hybrid 2048→512).`
fn rasters(lines: &[FrontierLine]) -> String {
    let mut by: Vec<(String, Vec<String>)> = Vec::new();
    for l in lines.iter().filter(|l| !l.raster.is_empty()) {
        match by.iter_mut().find(|(r, _)| *r == l.raster) {
            Some((_, configs)) if configs.contains(&l.map_config) => {}
            Some((_, configs)) => configs.push(l.map_config.clone()),
            None => by.push((l.raster.clone(), vec![l.map_config.clone()])),
        }
    }
    if by.is_empty() {
        return String::new();
    }
    let parts: Vec<String> = by
        .iter()
        .map(|(r, c)| format!("{r} ({})", c.join(", ")))
        .collect();
    format!("\nShadow-map raster: {}.\n", parts.join("; "))
}

/// The frontier as a ladder of error levels, adaptive settings against it, then every setting.
pub fn markdown(lines: &[FrontierLine]) -> String {
    let Some(first) = lines.first() else {
        return "# Frontier of fixed settings\n\nNo settings.\n".into();
    };
    let mut s = format!(
        "# Frontier of fixed settings: {}\n\n{} settings ({}); {}x{} screen; reference {}; median of {} timed frames; {} on {}.\n",
        first.core.scene,
        lines.len(),
        first.thinning,
        first.resolution[0],
        first.resolution[1],
        first.reference,
        first.repeats,
        first.clock.split(';').next().unwrap_or(&first.clock),
        first.core.adapter
    );
    s += &rasters(lines);
    // The budget's rows are judged against the frontier of the fixed settings, not part of it.
    let points: Vec<(f64, f64)> = lines.iter().map(FrontierLine::point).collect();
    s += "\n## The frontier: the cheapest setting for each error level\n\n\
          | RMSE at most | cheapest setting | maps | map size | median ms (min–max) | FLIP |\n|---:|---|---:|---:|---:|---:|\n";
    for i in front::ladder(&points)
        .into_iter()
        .filter(|&i| !lines[i].is_budget() && lines[i].failed.is_none())
    {
        let l = &lines[i];
        s += &format!(
            "| {:.5} | {} | {} | {} | {:.1} ({:.1}–{:.1}) | {} |\n",
            l.core.rmse,
            l.setting(),
            l.core.maps,
            l.core.map_size,
            l.core.frame_ms,
            l.frame_ms_min,
            l.frame_ms_max,
            flip(l)
        );
    }
    let certified: Vec<(&FrontierLine, &crate::record::Certified)> = lines
        .iter()
        .filter_map(|l| l.certify.as_ref().map(|c| (l, c)))
        .collect();
    if !certified.is_empty() {
        s += "\n## Certified error\n\nEach setting's RMSE beside its certified bound (`--certify`, docs/certify.md).\n\n| setting | RMSE | certified | covered |\n|---|---:|---|---|\n";
        for (l, c) in certified {
            s += &format!(
                "| {} | {:.5} | {} | {} |\n",
                l.setting(),
                l.core.rmse,
                c.line(),
                if c.bound >= l.core.rmse { "yes" } else { "no" }
            );
        }
    }
    s += &super::second_look::table(lines);
    let budget: Vec<&FrontierLine> = lines
        .iter()
        .filter(|l| l.is_budget() && l.failed.is_none())
        .collect();
    if !budget.is_empty() {
        s += "\n## The error budget against the frontier\n\n\
              `auto:target=T` chooses its grid per frame from the estimate (no reference), or one \
              filtered map where a finer grid predicts it meets T (1 map); its RMSE is measured, and its time set against the cheapest fixed setting that reaches the same RMSE.\n\n\
              | setting | maps | RMSE | RMSE / target | median ms | cheapest fixed setting at this RMSE | its RMSE | its ms | time ratio |\n|---|---:|---:|---:|---:|---|---:|---:|---:|\n";
        for l in &budget {
            let target = l.target().unwrap_or(f64::NAN);
            let rival = l
                .beaten_by
                .as_ref()
                .and_then(|b| lines.iter().find(|o| &o.setting() == b));
            let (name, e, t, ratio) = match rival {
                Some(r) => (
                    r.setting(),
                    format!("{:.5}", r.core.rmse),
                    format!("{:.1}", r.core.frame_ms),
                    format!("{:.2}×", l.core.frame_ms / r.core.frame_ms),
                ),
                None => ("none reaches it".into(), "-".into(), "-".into(), "-".into()),
            };
            s += &format!(
                "| {} | {} | {:.5} | {:.2} | {:.1} | {name} | {e} | {t} | {ratio} |\n",
                l.core.spec,
                l.core.maps,
                l.core.rmse,
                l.core.rmse / target,
                l.core.frame_ms
            );
        }
        s += &super::budget::table(lines, &budget);
    }
    let adaptive: Vec<&FrontierLine> = lines
        .iter()
        .filter(|l| l.is_adaptive() && l.failed.is_none())
        .collect();
    if !adaptive.is_empty() {
        s += "\n## Adaptive and local refinement against the frontier\n\n\
              | setting | maps | RMSE | median ms | on the frontier | beaten by | its RMSE | its ms |\n|---|---:|---:|---:|---|---|---:|---:|\n";
        for l in adaptive {
            let rival = l
                .beaten_by
                .as_ref()
                .and_then(|b| lines.iter().find(|o| &o.setting() == b));
            let (name, e, t) = match rival {
                Some(r) => (
                    r.setting(),
                    format!("{:.5} ({:.2}×)", r.core.rmse, r.core.rmse / l.core.rmse),
                    format!(
                        "{:.1} ({:.2}×)",
                        r.core.frame_ms,
                        r.core.frame_ms / l.core.frame_ms
                    ),
                ),
                None => ("-".into(), "-".into(), "-".into()),
            };
            s += &format!(
                "| {} | {} | {:.5} | {:.1} | {} | {name} | {e} | {t} |\n",
                l.setting(),
                l.core.maps,
                l.core.rmse,
                l.core.frame_ms,
                if l.on_frontier { "yes" } else { "no" }
            );
        }
    }
    s += "\n## Every setting\n\n| setting | kind | maps | map size | RMSE | FLIP | median ms (min–max) | on the frontier |\n|---|---|---:|---:|---:|---:|---:|---|\n";
    for l in lines {
        if let Some(reason) = &l.failed {
            s += &format!(
                "| {} | {} | failed: {} | | | | | |\n",
                l.setting(),
                l.kind,
                reason.replace('|', "\\|")
            );
            continue;
        }
        s += &format!(
            "| {} | {} | {} | {} | {:.5} | {} | {:.1} ({:.1}–{:.1}) | {} |\n",
            l.setting(),
            l.kind,
            l.core.maps,
            l.core.map_size,
            l.core.rmse,
            flip(l),
            l.core.frame_ms,
            l.frame_ms_min,
            l.frame_ms_max,
            if l.on_frontier { "yes" } else { "" }
        );
    }
    s
}
