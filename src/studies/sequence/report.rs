//! The sequence's tables and HTML: CSV of frames and summaries, a report section (an HTML fragment
//! that the main job's report also embeds) and a self-contained page around sections.

use super::{FrameRow, MethodSummary, SequenceOutcome};
use crate::{Error, Result};
use base64::Engine;
use minijinja::value::{Serde, Value};
use minijinja::Environment;
use serde::Serialize;
use std::path::Path;

const SECTION: &str = include_str!("section.html");
const PAGE: &str = include_str!("page.html");

pub fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes))
}

/// A CSV field, quoted as in results.csv when it holds a comma or a quote.
fn field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

pub fn frames_csv(rows: &[FrameRow]) -> String {
    let mut s = String::from(
        "scene,label,frame,shadow_maps,total_ms,rmse,mae,max_abs,bad_pixel_share,flip_mean,temporal_rmse,popping_share,popping_pixels,temporal_pixels\n",
    );
    for r in rows {
        let t = r.temporal;
        let opt = |v: Option<String>| v.unwrap_or_default();
        s += &format!(
            "{},{},{},{},{:.3},{:.6},{:.6},{:.6},{:.6},{:.6},{},{},{},{}\n",
            field(&r.scene),
            field(&r.label),
            r.frame,
            r.shadow_maps,
            r.total_ms,
            r.metrics.rmse,
            r.metrics.mae,
            r.metrics.max_abs,
            r.metrics.bad_pixel_share,
            r.metrics.flip_mean,
            opt(t.map(|t| format!("{:.6}", t.temporal_rmse))),
            opt(t.map(|t| format!("{:.6}", t.popping_share))),
            opt(t.map(|t| t.popping_pixels.to_string())),
            opt(t.map(|t| t.pixels.to_string())),
        );
    }
    s
}

pub fn summary_csv(rows: &[MethodSummary]) -> String {
    let mut s = String::from(
        "label,frames,mean_rmse,mean_bad_pixel_share,temporal_rmse,popping_share,popping_pixels,maps_mean,maps_min,maps_max,median_ms\n",
    );
    for m in rows {
        s += &format!(
            "{},{},{:.6},{:.6},{:.6},{:.6},{},{:.2},{},{},{:.3}\n",
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
            m.median_ms
        );
    }
    s
}

#[derive(Serialize)]
struct Figure {
    caption: String,
    uri: String,
}

#[derive(Serialize)]
struct SectionView<'a> {
    title: &'a str,
    settings: Vec<(&'static str, String)>,
    header: Vec<&'static str>,
    rows: Vec<Vec<String>>,
    charts: Vec<Figure>,
    animations: Vec<Figure>,
    sentences: Vec<String>,
}

/// One line per method from the figures: the frame where it pops most, or that it never pops.
pub fn pop_sentences(summaries: &[MethodSummary], pixels_per_frame: u64) -> Vec<String> {
    summaries
        .iter()
        .map(|m| match m.worst_pop_frame {
            Some((frame, pops)) if pops > 0 => format!(
                "{} pops most in frame {frame}: {pops} of {pixels_per_frame} geometry pixels change by more than 1/32 while the reference changes by less than 1/256 ({} popping pixels over the sequence, {:.3}%).",
                m.label,
                m.temporal.popping_pixels,
                100.0 * m.temporal.popping_share
            ),
            _ => format!("{} never pops: no pixel changes by more than 1/32 where the reference stays within 1/256.", m.label),
        })
        .collect()
}

/// For a method whose map count changes: the largest jump between two frames, and the pops there.
pub fn decision_sentence(label: &str, rows: &[FrameRow]) -> Option<String> {
    let mine: Vec<&FrameRow> = rows.iter().filter(|r| r.label == label).collect();
    let (a, b) = mine
        .windows(2)
        .map(|w| (w[0], w[1]))
        .max_by(|x, y| x.0.shadow_maps.abs_diff(x.1.shadow_maps).cmp(&y.0.shadow_maps.abs_diff(y.1.shadow_maps)).then(y.1.frame.cmp(&x.1.frame)))?;
    if a.shadow_maps == b.shadow_maps {
        return None;
    }
    let pops = b.temporal.map_or(0, |t| t.popping_pixels);
    Some(format!(
        "{label}'s decision changes most between frames {} and {}: {} → {} shadow maps, and {pops} pixels pop in frame {}.",
        a.frame, b.frame, a.shadow_maps, b.shadow_maps, b.frame
    ))
}

/// Every sentence of a sequence section: pops per method, then each decision's largest jump.
pub fn sentences(o: &SequenceOutcome) -> Vec<String> {
    let pixels = o.rows.iter().find_map(|r| r.temporal.map(|t| t.pixels)).unwrap_or(0);
    let mut out = pop_sentences(&o.summaries, pixels);
    out.extend(o.summaries.iter().filter_map(|m| decision_sentence(&m.label, &o.rows)));
    out
}

fn render(template: &str, name: &str, ctx: &impl Serialize) -> Result<String> {
    let mut env = Environment::new();
    let err = |e: minijinja::Error| Error::Io { path: format!("<{name} template>"), message: e.to_string() };
    env.add_template(name, template).map_err(err)?;
    env.get_template(name).map_err(err)?.render(Value::from(Serde(ctx))).map_err(err)
}

/// The section: settings, the per-method table, the charts and the animations.
pub fn section(o: &SequenceOutcome) -> Result<String> {
    let rows = o
        .summaries
        .iter()
        .map(|m| {
            vec![
                m.label.clone(),
                format!("{:.4}", m.mean_rmse),
                format!("{:.2}", 100.0 * m.mean_bad_pixel_share),
                format!("{:.4}", m.temporal.temporal_rmse),
                format!("{:.3}", 100.0 * m.temporal.popping_share),
                m.temporal.popping_pixels.to_string(),
                if m.maps_min == m.maps_max { m.maps_min.to_string() } else { format!("{:.1} ({}–{})", m.maps_mean, m.maps_min, m.maps_max) },
                format!("{:.1}", m.median_ms),
            ]
        })
        .collect();
    let frames = o.summaries.first().map_or(0, |m| m.frames);
    let view = SectionView {
        title: &o.title,
        settings: vec![
            ("motion", o.description.clone()),
            ("frames", frames.to_string()),
            ("resolution", format!("{}x{}", o.resolution[0], o.resolution[1])),
            ("reference", format!("{}, one per frame", o.reference)),
            ("adapter", o.adapter.clone()),
            ("clock", "wall clock of one frame-mode frame per method and frame (no repeats), median over frames".into()),
        ],
        header: vec![
            "method",
            "mean RMSE",
            "mean bad pixels %",
            "temporal RMSE",
            "popping %",
            "popping pixels",
            "maps per frame",
            "median ms",
        ],
        rows,
        charts: o.charts.iter().map(|(_, caption, svg)| Figure { caption: caption.clone(), uri: data_uri("image/svg+xml", svg.as_bytes()) }).collect(),
        animations: o.animations.iter().map(|(caption, bytes)| Figure { caption: caption.clone(), uri: data_uri("image/png", bytes) }).collect(),
        sentences: sentences(o),
    };
    render(SECTION, "section.html", &view)
}

/// A whole self-contained page around rendered sections.
pub fn page(title: &str, sections: &[String]) -> Result<String> {
    render(PAGE, "page.html", &serde_json::json!({ "title": title, "sections": sections }))
}

/// Writes the files as one set (crate::record::output_set): all of them, or on failure what was there.
pub fn write_set(out: &Path, files: &[(String, Vec<u8>)]) -> Result<()> {
    crate::record::run_files::write_files(out, files).map(|_| ())
}

/// Inserts sections before `</body>` of a report page written earlier (the main job's report).
pub fn append_to_page(html: &Path, sections: &[String]) -> Result<()> {
    let text = std::fs::read_to_string(html).map_err(|e| Error::io(html, e))?;
    let merged = insert_before_body(&text, sections)
        .ok_or_else(|| Error::Io { path: html.display().to_string(), message: "no </body> to insert the sections before".into() })?;
    // One file of an existing set: replaced through a temporary name, the rest of the set kept.
    let dir = html.parent().unwrap_or(Path::new("."));
    let name = html.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.tmp"));
    std::fs::write(&tmp, merged).map_err(|e| Error::io(&tmp, e))?;
    std::fs::rename(&tmp, html).map_err(|e| Error::io(html, e))
}

/// `text` with the sections before its last `</body>`; `None` when it has none.
pub fn insert_before_body(text: &str, sections: &[String]) -> Option<String> {
    let at = text.rfind("</body>")?;
    Some(format!("{}{}\n{}", &text[..at], sections.concat(), &text[at..]))
}

/// The per-method figures as a plain-text table for the terminal.
pub fn summary_table(rows: &[MethodSummary]) -> String {
    let mut s = format!(
        "{:<28} {:>10} {:>13} {:>10} {:>8} {:>16} {:>10}\n",
        "method", "mean RMSE", "temporal RMSE", "popping %", "pops", "maps per frame", "median ms"
    );
    for m in rows {
        let maps = if m.maps_min == m.maps_max { m.maps_min.to_string() } else { format!("{:.1} ({}-{})", m.maps_mean, m.maps_min, m.maps_max) };
        s += &format!(
            "{:<28} {:>10.4} {:>13.4} {:>10.3} {:>8} {:>16} {:>10.1}\n",
            m.label,
            m.mean_rmse,
            m.temporal.temporal_rmse,
            100.0 * m.temporal.popping_share,
            m.temporal.popping_pixels,
            maps,
            m.median_ms
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::Metrics;
    use crate::studies::sequence::temporal::FramePair;

    fn row(label: &str, frame: u32, maps: u32, pops: u64) -> FrameRow {
        FrameRow {
            scene: "s".into(),
            label: label.into(),
            method: "adaptive".into(),
            params: serde_json::json!({}),
            frame,
            shadow_maps: maps,
            total_ms: 1.0,
            metrics: Metrics::default(),
            temporal: (frame > 0).then_some(FramePair { popping_pixels: pops, pixels: 100, ..Default::default() }),
            light_center: [0.0; 3],
            camera_eye: [0.0; 3],
        }
    }

    #[test]
    fn the_largest_decision_jump_is_named_with_its_pops() {
        let rows = [row("a", 0, 4, 0), row("a", 1, 4, 0), row("a", 2, 264, 37), row("a", 3, 226, 5), row("b", 0, 9, 0), row("b", 1, 9, 0)];
        assert_eq!(
            decision_sentence("a", &rows).unwrap(),
            "a's decision changes most between frames 1 and 2: 4 → 264 shadow maps, and 37 pixels pop in frame 2."
        );
        assert_eq!(decision_sentence("b", &rows), None);
    }

    #[test]
    fn sections_go_before_the_last_body_tag() {
        let page = "<html><body><p>x</p></body></html>";
        assert_eq!(insert_before_body(page, &["<s>1</s>".into(), "<s>2</s>".into()]).unwrap(), "<html><body><p>x</p><s>1</s><s>2</s>\n</body></html>");
        assert_eq!(insert_before_body("<html>", &[]), None);
    }
}
