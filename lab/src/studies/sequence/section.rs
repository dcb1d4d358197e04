//! The sequence's report section: an HTML fragment (settings, the per-method table, sentences,
//! charts, animations) that its own page, the failure gallery and the main job's report embed.

use super::{FrameRow, MethodSummary, SequenceOutcome};
use crate::report::page::{data_uri, render};
use crate::Result;
use serde::Serialize;

const SECTION: &str = include_str!("section.html");

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
    let (a, b) = mine.windows(2).map(|w| (w[0], w[1])).max_by(|x, y| {
        x.0.core
            .maps
            .abs_diff(x.1.core.maps)
            .cmp(&y.0.core.maps.abs_diff(y.1.core.maps))
            .then(y.1.frame.cmp(&x.1.frame))
    })?;
    if a.core.maps == b.core.maps {
        return None;
    }
    let pops = b.temporal.map_or(0, |t| t.popping_pixels);
    Some(format!(
        "{label}'s decision changes most between frames {} and {}: {} → {} shadow maps, and {pops} pixels pop in frame {}.",
        a.frame, b.frame, a.core.maps, b.core.maps, b.frame
    ))
}

/// Every sentence of a sequence section: pops per method, then each decision's largest jump.
pub fn sentences(o: &SequenceOutcome) -> Vec<String> {
    let pixels = o
        .rows
        .iter()
        .find_map(|r| r.temporal.map(|t| t.pixels))
        .unwrap_or(0);
    let mut out = pop_sentences(&o.summaries, pixels);
    out.extend(
        o.summaries
            .iter()
            .filter_map(|m| decision_sentence(&m.label, &o.rows)),
    );
    out
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
                if m.maps_min == m.maps_max {
                    m.maps_min.to_string()
                } else {
                    format!("{:.1} ({}–{})", m.maps_mean, m.maps_min, m.maps_max)
                },
                format!("{:.1}", m.median_ms),
                format!("{:.1}", m.median_ms_after_first),
                m.time_ratio_to_without_reuse
                    .map_or("–".to_string(), |r| format!("{r:.3}")),
                format!(
                    "{:.1} / {:.1}",
                    m.rendered_mean_after_first, m.kept_mean_after_first
                ),
                m.v_equal_frames
                    .map_or("–".to_string(), |(e, n)| format!("{e} of {n}")),
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
            "median ms after frame 0",
            "time over reuse off (median of frame pairs)",
            "maps rendered / kept after frame 0",
            "V equal without reuse",
        ],
        rows,
        charts: o.charts.iter().map(|(_, caption, svg)| Figure { caption: caption.clone(), uri: data_uri("image/svg+xml", svg.as_bytes()) }).collect(),
        animations: o.animations.iter().map(|(caption, bytes)| Figure { caption: caption.clone(), uri: data_uri("image/png", bytes) }).collect(),
        sentences: sentences(o),
    };
    render(SECTION, "section.html", &view)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::Metrics;
    use crate::studies::sequence::temporal::FramePair;

    fn row(label: &str, frame: u32, maps: u32, pops: u64) -> FrameRow {
        FrameRow {
            core: crate::record::RowCore {
                scene: "s".into(),
                method: "adaptive".into(),
                maps,
                frame_ms: 1.0,
                ..Default::default()
            },
            label: label.into(),
            frame,
            metrics: Metrics::default(),
            temporal: (frame > 0).then_some(FramePair {
                popping_pixels: pops,
                pixels: 100,
                ..Default::default()
            }),
            light_center: [0.0; 3],
            camera_eye: [0.0; 3],
            reuse: false,
            reuse_counts: Default::default(),
            v_equal_without_reuse: None,
            kept_bytes: 0,
            stages_ms: Default::default(),
        }
    }

    #[test]
    fn the_largest_decision_jump_is_named_with_its_pops() {
        let rows = [
            row("a", 0, 4, 0),
            row("a", 1, 4, 0),
            row("a", 2, 264, 37),
            row("a", 3, 226, 5),
            row("b", 0, 9, 0),
            row("b", 1, 9, 0),
        ];
        assert_eq!(
            decision_sentence("a", &rows).unwrap(),
            "a's decision changes most between frames 1 and 2: 4 → 264 shadow maps, and 37 pixels pop in frame 2."
        );
        assert_eq!(decision_sentence("b", &rows), None);
    }
}
