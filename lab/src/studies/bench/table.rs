//! The suite's files: table2.md in the seed's shape (our figures beside the seed's) and
//! results.jsonl (one line per scene and method, every figure the table is made from).

use super::errors::PENDING;
use super::fair;
use super::seed::SEED_SETUP;
use super::suite::{MethodResult, SceneResult, SuiteResults};
use std::fmt::Write;

/// `1234567` → `1,234,567`.
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// Three significant figures: CPU-adapter frame rates are often below 1 fps.
fn fps(x: f64) -> String {
    match x {
        x if x >= 100.0 => format!("{x:.0}"),
        x if x >= 10.0 => format!("{x:.1}"),
        x if x >= 1.0 => format!("{x:.2}"),
        x => format!("{x:.3}"),
    }
}

fn errors(m: &MethodResult) -> String {
    match &m.errors {
        Some(e) => format!("{:.4} / {:.4}", e.rmse, e.flip),
        None => "—".into(),
    }
}

/// A method's fps, or why it has none.
fn fps_of(m: &MethodResult) -> String {
    match &m.failed {
        Some(reason) => format!("failed: {}", reason.replace('|', "\\|")),
        None => fps(m.fps()),
    }
}

/// `grid / adaptive` as `1.23x`, "—" where either failed.
fn ratio(grid: &MethodResult, adaptive: &MethodResult) -> String {
    if grid.failed.is_some() || adaptive.failed.is_some() {
        "—".into()
    } else {
        format!("{:.2}x", grid.frame_ms.median / adaptive.frame_ms.median)
    }
}

fn maps(m: &MethodResult) -> String {
    if m.failed.is_some() {
        return "—".into();
    }
    if m.maps_stable {
        m.maps.to_string()
    } else {
        format!("{}, varied", m.maps)
    }
}

/// `2026-11-21 22:50 UTC` from Unix seconds (civil-from-days, proleptic Gregorian).
pub fn utc(unix_s: u64) -> String {
    let days = (unix_s / 86_400) as i64;
    let (h, mi) = ((unix_s % 86_400) / 3600, (unix_s % 3600) / 60);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02} {h:02}:{mi:02} UTC")
}

pub fn markdown(r: &SuiteResults) -> String {
    let a = &r.adapter;
    let first = r.scenes.first();
    let label = |f: fn(&SceneResult) -> &MethodResult| {
        first.map(|s| f(s).label.clone()).unwrap_or_default()
    };
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Seed 000, Table 2, reproduced: adaptive vs regular light-source sampling\n"
    );
    let _ = writeln!(
        md,
        "Adapter: **{}** ({}, {}, driver {} {}). Run {}, {:.0} s in all.  ",
        a.name,
        a.backend,
        a.device_type,
        a.driver,
        a.driver_info,
        utc(r.started_unix_s),
        r.wall_s
    );
    let seed_like = r.scenes.iter().all(|s| s.settings == [512, 512, 512]);
    let settings = if seed_like {
        "as in the seed: 512x512 screen, 512x512 Depth32Float shadow maps".to_string()
    } else {
        let each: Vec<String> = r
            .scenes
            .iter()
            .map(|s| {
                format!(
                    "{} {}x{} / {}²",
                    s.seed.scene, s.settings[0], s.settings[1], s.settings[2]
                )
            })
            .collect();
        format!("NOT the seed's 512x512 / 512²: {}", each.join(", "))
    };
    let _ = writeln!(
        md,
        "Settings {settings}. Adaptive = `{}`, regular = `{}`, in the same run.  ",
        label(|s| &s.adaptive),
        label(|s| &s.regular)
    );
    let _ = writeln!(
        md,
        "Clock: wall clock per frame (first submit to the last read-back, TimingMode::Frame), median of {} frames after one warm-up frame and one stages-mode frame per method, the methods (adaptive, regular, fair grid{}) interleaved. {}\n",
        r.repeats,
        if r.scenes.iter().any(|s| s.regions.is_some()) { ", per region" } else { "" },
        if r.timestamps_trusted { "GPU timestamps: not yet wired into this table." } else { "GPU timestamps are not trustworthy on this (CPU) adapter and are not used." }
    );
    let _ = writeln!(md, "fps (shadow maps); speed-up = adaptive fps / regular fps, as in the seed. Seed: {SEED_SETUP}.\n");
    let _ = writeln!(md, "| scene | triangles (seed) | adaptive fps (maps) | regular fps (maps) | speed-up | adaptive RMSE / FLIP | regular RMSE / FLIP | seed adaptive | seed regular | seed speed-up |");
    let _ = writeln!(md, "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for s in &r.scenes {
        let seed = s.seed;
        let _ = writeln!(
            md,
            "| {} {} | {} ({}.{}k) | {} ({}) | {} ({}) | {} | {} | {} | {:.2} ({}) | {:.2} ({}) | {:.1}x |",
            seed.scene,
            seed.seed_name,
            thousands(s.triangles as u64),
            thousands(seed.triangles / 1000),
            seed.triangles % 1000 / 100,
            fps_of(&s.adaptive),
            maps(&s.adaptive),
            fps_of(&s.regular),
            maps(&s.regular),
            ratio(&s.regular, &s.adaptive),
            errors(&s.adaptive),
            errors(&s.regular),
            seed.adaptive_fps,
            seed.adaptive_maps,
            seed.regular_fps,
            seed.regular_maps,
            seed.speedup()
        );
    }
    let errs = match &r.reference {
        Some(label) => format!("Errors against the {label} reference, over geometry pixels."),
        None => format!("Error columns: {PENDING}."),
    };
    let _ = writeln!(md, "\n{errs}\n");
    fair_rows(&mut md, r);
    region_rows(&mut md, r);
    let _ = writeln!(md, "## Frame times (ms, wall clock)\n");
    let _ = writeln!(
        md,
        "| scene | method | maps | median | min | max | setup (not in the frame) | read-backs |"
    );
    let _ = writeln!(md, "|---|---|---:|---:|---:|---:|---:|---:|");
    for s in &r.scenes {
        for m in s.methods() {
            if let Some(reason) = &m.failed {
                let _ = writeln!(
                    md,
                    "| {} | `{}` | failed: {} | | | | | |",
                    s.seed.scene,
                    m.label,
                    reason.replace('|', "\\|")
                );
                continue;
            }
            let f = &m.frame_ms;
            let _ = writeln!(
                md,
                "| {} | `{}` | {} | {:.1} | {:.1} | {:.1} | {:.1} | {} |",
                s.seed.scene,
                m.label,
                maps(m),
                f.median,
                f.min,
                f.max,
                m.setup_ms.median,
                m.syncs
            );
        }
    }
    let files = r
        .scenes
        .iter()
        .map(|s| format!("`{}`", s.file.display()))
        .collect::<Vec<_>>()
        .join(", ");
    let sets = if r.sets.is_empty() {
        String::new()
    } else {
        format!(
            ", with {}",
            r.sets
                .iter()
                .map(|s| format!("`--set {s}`"))
                .collect::<Vec<_>>()
                .join(" ")
        )
    };
    let _ = writeln!(
        md,
        "\nScene files: {files}{sets}. Per-stage times and every sample: results.jsonl."
    );
    md
}

/// Adaptive against the seed's lattice and against the centred grid with about its map count:
/// both speed-ups (median frame times), both RMSEs and a verdict per row (fair::verdict).
fn fair_rows(md: &mut String, r: &SuiteResults) {
    let _ = writeln!(md, "## Fair rows: adaptive against the seed's lattice and the centred grid of about its map count\n");
    let _ = writeln!(md, "Speed-up = grid median frame / adaptive median frame (> 1: adaptive is faster). Fair grid: `regular:n=N,layout=centred`, N² the square nearest to the adaptive maps of one untimed frame (N ≥ 2).\n");
    let _ = writeln!(md, "| scene | grid | grid maps | adaptive maps | speed-up | seed speed-up | adaptive RMSE | grid RMSE | verdict |");
    let _ = writeln!(md, "|---|---|---:|---:|---:|---:|---:|---:|---|");
    let rmse = |m: &MethodResult| {
        m.errors
            .as_ref()
            .map_or("—".to_string(), |e| format!("{:.5}", e.rmse))
    };
    for s in &r.scenes {
        let adaptive_maps = if s.probe_held() {
            maps(&s.adaptive)
        } else {
            format!("{} (untimed frame: {})", maps(&s.adaptive), s.probe_maps)
        };
        for (grid, seed) in [
            (&s.regular, format!("{:.1}x", s.seed.speedup())),
            (&s.fair, "—".to_string()),
        ] {
            let speedup = ratio(grid, &s.adaptive);
            let verdict = match (&s.adaptive.failed, &grid.failed) {
                (None, None) => fair::verdict(&s.adaptive.row, &grid.row),
                _ => "—: a failed setting".to_string(),
            };
            let _ = writeln!(
                md,
                "| {} | `{}` | {} | {} | {} | {} | {} | {} | {} |",
                s.seed.scene,
                grid.label,
                maps(grid),
                adaptive_maps,
                speedup,
                seed,
                rmse(&s.adaptive),
                rmse(grid),
                verdict
            );
        }
    }
    let _ = writeln!(md, "\nVerdict: `adaptive dominates` when its median frame and RMSE are both at most the grid's; `grid dominates` when it is slower and its RMSE at least the grid's; otherwise the trade-off (speed-up, RMSE ratio).\n");
}

/// The per-region method against the same two grids: both speed-ups, the RMSEs and a verdict on
/// each (the fair grid is the one matched to adaptive's map count, so the per-region method meets
/// the grid that the adaptive row met, in the same run).
fn region_rows(md: &mut String, r: &SuiteResults) {
    if r.scenes.iter().all(|s| s.regions.is_none()) {
        return;
    }
    let label = r
        .scenes
        .iter()
        .find_map(|s| s.regions.as_ref())
        .map(|m| m.label.clone())
        .unwrap_or_default();
    let _ = writeln!(
        md,
        "## Per region: `{label}` against the seed's lattice and the fair grid\n"
    );
    let _ = writeln!(
        md,
        "Speed-up = grid median frame / per-region median frame (> 1: per region is faster).\n"
    );
    let _ = writeln!(md, "| scene | per-region maps | per-region ms | per-region RMSE | lattice speed-up | lattice RMSE | verdict against the lattice | fair grid | fair speed-up | fair RMSE | verdict against the fair grid |");
    let _ = writeln!(md, "|---|---:|---:|---:|---:|---:|---|---|---:|---:|---|");
    let rmse = |m: &MethodResult| {
        m.errors
            .as_ref()
            .map_or("—".to_string(), |e| format!("{:.5}", e.rmse))
    };
    let verdict = |m: &MethodResult, grid: &MethodResult| match (&m.failed, &grid.failed) {
        (None, None) => fair::verdict_of("per region", &m.row, &grid.row),
        _ => "—: a failed setting".to_string(),
    };
    for s in &r.scenes {
        let Some(m) = &s.regions else { continue };
        let ms = if m.failed.is_some() {
            fps_of(m)
        } else {
            format!("{:.1}", m.frame_ms.median)
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | `{}` | {} | {} | {} |",
            s.seed.scene,
            maps(m),
            ms,
            rmse(m),
            ratio(&s.regular, m),
            rmse(&s.regular),
            verdict(m, &s.regular),
            s.fair.label,
            ratio(&s.fair, m),
            rmse(&s.fair),
            verdict(m, &s.fair)
        );
    }
    let _ = writeln!(md);
}

/// `results.jsonl`: the record layer's rows (the schema of `compare` and `sweep`), one line per
/// scene and method.
pub fn jsonl(r: &SuiteResults) -> crate::Result<String> {
    crate::record::jsonl(&r.rows())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_and_numbers() {
        assert_eq!(utc(0), "1970-01-01 00:00 UTC");
        assert_eq!(utc(1_795_300_000), "2026-11-21 22:26 UTC");
        assert_eq!(thousands(1_206_530), "1,206,530");
        assert_eq!(thousands(999), "999");
        assert_eq!(fps(0.0312), "0.031");
        assert_eq!(fps(19.891), "19.9");
    }
}
