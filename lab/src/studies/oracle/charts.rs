//! The oracle's pictures: each tile's choice (one colour per class, free tiles grey), and
//! `gain_bound` against the target, a line per scene, screen and menu.

use super::OracleRow;
use crate::report::charts::scatter::{push_point, render, Point, Scatter};
use crate::report::charts::ChartError;

/// Pixels per tile in the picture.
const CELL: u32 = 14;
const FREE: &str = "#e4e4e4";
const NO_GEOMETRY: &str = "#ffffff";

/// A class's colour: the chart palette's.
fn colour(i: usize) -> String {
    let c = crate::report::charts::style::colour(i);
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The tiles' choices of one row as an SVG: the screen's tiles, each filled with its class's
/// colour, and a legend with each class's candidate, tiles and penumbra share.
pub fn tiles_svg(r: &OracleRow) -> String {
    let (gw, gh) = (r.tile_cols * CELL, r.tile_rows * CELL);
    let legend_x = gw + 16;
    let lines = r.split.len() + 3;
    let height = (gh + 40).max(40 + 18 * lines as u32);
    // The legend's longest line and the title at about 7 px a character.
    let longest = r
        .split
        .iter()
        .map(|c| c.candidate.len() + c.kind.name().len() + 40)
        .max()
        .unwrap_or(40)
        .max(44);
    let width =
        (legend_x + 24 + 7 * longest as u32).max(8 * 40 + 7 * r.scene.chars().count() as u32);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"{width}\" height=\"{height}\" fill=\"#ffffff\"/>\n"
    );
    let title = match (r.oracle_ms, r.gain_bound) {
        (Some(ms), Some(g)) => format!(
            "{} {}², T = {}, {}: oracle {ms:.1} ms, bound {g:.2}×",
            r.scene, r.resolution, r.target, r.menu
        ),
        (Some(ms), None) => format!(
            "{} {}², T = {}, {}: oracle {ms:.1} ms (no single setting meets T)",
            r.scene, r.resolution, r.target, r.menu
        ),
        _ => format!(
            "{} {}², T = {}, {}: no choice meets T",
            r.scene, r.resolution, r.target, r.menu
        ),
    };
    s += &format!(
        "<text x=\"4\" y=\"16\" font-size=\"13\">{}</text>\n<g transform=\"translate(0,28)\">\n",
        escape(&title)
    );
    for (i, &c) in r.choice.iter().enumerate() {
        let (x, y) = (i as u32 % r.tile_cols * CELL, i as u32 / r.tile_cols * CELL);
        let fill = match c {
            -1 => FREE.to_string(),
            c if c < 0 => NO_GEOMETRY.to_string(),
            c => colour(c as usize),
        };
        s += &format!("<rect x=\"{x}\" y=\"{y}\" width=\"{CELL}\" height=\"{CELL}\" fill=\"{fill}\" stroke=\"#ffffff\" stroke-width=\"0.5\"/>\n");
    }
    s += &format!(
        "<rect x=\"0\" y=\"0\" width=\"{gw}\" height=\"{gh}\" fill=\"none\" stroke=\"#888888\"/>\n"
    );
    let mut y = 0;
    let mut entry = |fill: &str, text: String| {
        s += &format!("<rect x=\"{legend_x}\" y=\"{y}\" width=\"12\" height=\"12\" fill=\"{fill}\" stroke=\"#888888\" stroke-width=\"0.5\"/><text x=\"{}\" y=\"{}\">{}</text>\n", legend_x + 18, y + 11, escape(&text));
        y += 18;
    };
    for (i, c) in r.split.iter().enumerate() {
        entry(
            &colour(i),
            format!(
                "{} ({}): {} tiles, {:.0}% penumbra",
                c.candidate,
                c.kind.name(),
                c.tiles,
                100.0 * c.penumbra_share
            ),
        );
    }
    entry(
        FREE,
        format!("free (uniformly lit or dark): {} tiles", r.free_tiles),
    );
    entry(NO_GEOMETRY, "no geometry".to_string());
    s += "</g>\n</svg>\n";
    s
}

/// `gain_bound` against the target: a line per scene, screen and menu.
pub fn gain_svg(rows: &[OracleRow]) -> Result<String, ChartError> {
    let mut series = Vec::new();
    for r in rows {
        if let Some(g) = r.gain_bound {
            push_point(
                &mut series,
                format!("{} {}² {}", r.scene, r.resolution, r.menu),
                Point {
                    x: r.target,
                    y: g,
                    label: None,
                    x_span: None,
                    hit: None,
                },
            );
        }
    }
    if series.is_empty() {
        return Err(ChartError::NoData(
            "needs a row with a single setting and an oracle meeting its target",
        ));
    }
    render(&Scatter {
        title: "The most choosing per tile could gain: gain_bound against the target".into(),
        x_desc: "target T (RMSE of V), log scale".into(),
        y_desc: "gain_bound: the cheapest single setting meeting T over the oracle's bound".into(),
        series,
        connect: true,
        front: None,
        front_label: "",
        x_log: true,
        y_log: false,
    })
}
