//! Chart (d): stacked horizontal bars of stage times, one bar per row, one colour per stage.

use plotters::coord::combinators::BindKeyPoints;
use plotters::prelude::*;

use super::scatter::tick_label;
use super::style::{colour, plot_err, spans_scenes, with_scene, AXIS_PX, FONT, LABEL_PX, TITLE_PX};
use super::{ChartError, ResultRow};

/// Chart (d'): each row's stages summed into the frame split (raster, decision, shade, waits;
/// `crate::gpu::stages`), drawn like the stage breakdown.
pub fn frame_split_svg(rows: &[ResultRow]) -> Result<String, ChartError> {
    let split: Vec<ResultRow> = rows
        .iter()
        .map(|r| {
            let mut r = r.clone();
            r.stages_ms = crate::gpu::stages::frame_split(&r.stages_ms)
                .into_iter()
                .map(|(k, v)| (k.to_string(), v))
                .collect();
            r
        })
        .collect();
    bars_svg(
        &split,
        "Frame split: raster, decision, shade, waits (wall clock)",
    )
}

/// Rows top to bottom in the given order. Stages are stacked in the order of their first
/// appearance over the rows (each row's `stages_ms` is sorted by name); negative or
/// non-finite stage times are skipped.
pub fn stage_breakdown_svg(rows: &[ResultRow]) -> Result<String, ChartError> {
    bars_svg(rows, "Stage time breakdown (wall clock per stage)")
}

fn bars_svg(rows: &[ResultRow], title: &str) -> Result<String, ChartError> {
    let rows: Vec<&ResultRow> = rows.iter().filter(|r| !r.stages_ms.is_empty()).collect();
    if rows.is_empty() {
        return Err(ChartError::NoData("needs rows with stage times"));
    }
    let ok = |v: f64| v.is_finite() && v >= 0.0;
    let mut stages: Vec<&str> = Vec::new();
    for r in &rows {
        for k in r.stages_ms.keys() {
            if !stages.contains(&k.as_str()) {
                stages.push(k);
            }
        }
    }
    let multi = spans_scenes(rows.iter().copied());
    let labels: Vec<String> = rows
        .iter()
        .map(|r| with_scene(multi, &r.core.scene, &r.label()))
        .collect();
    let total = |r: &ResultRow| {
        r.stages_ms
            .values()
            .copied()
            .filter(|&v| ok(v))
            .sum::<f64>()
    };

    // Bar height and label area grow with the data so long labels and many rows stay legible.
    let n = rows.len();
    let longest = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0) as u32;
    let y_area = (longest * 8 + 16).clamp(80, 420);
    let size = (
        960 + y_area.saturating_sub(200),
        (n as u32 * 36 + 160).max(320),
    );
    // Keep the right end of the x range free for the legend so it never covers a bar.
    let longest_stage = stages.iter().map(|s| s.chars().count()).max().unwrap_or(0) as f64;
    let plot_px = f64::from(size.0 - y_area - 32);
    let legend_share = ((longest_stage * 8.0 + 60.0) / plot_px).min(0.6);
    let t_max = rows.iter().map(|r| total(r)).fold(0.0, f64::max).max(1e-6);
    let x_max = t_max * 1.02 / (1.0 - legend_share);

    // Slot 0 is at the bottom: the first row goes to the top slot.
    let centres: Vec<i32> = (0..n as i32).map(|k| 2 * k + 1).collect();
    let slot_row =
        |y: i32| (y % 2 == 1 && y > 0 && y < 2 * n as i32).then(|| n - 1 - (y / 2) as usize);

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, (FONT, TITLE_PX))
            .margin(16)
            .x_label_area_size(56)
            .y_label_area_size(y_area)
            // Row slot k spans y ∈ [2k, 2k+2] with its label tick at the centre 2k+1 (plotters'
            // segmented axes need ≥ 2 segments, and float axes cannot take custom ticks).
            .build_cartesian_2d(0.0..x_max, (0..2 * n as i32).with_key_points(centres))
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .disable_y_mesh()
            .x_desc("time (ms): stage times stacked in first-seen order; compare: one stages-mode frame")
            .y_desc("method")
            .y_label_formatter(&|v| {
                slot_row(*v)
                    .and_then(|i| labels.get(i))
                    .cloned()
                    .unwrap_or_default()
            })
            .axis_desc_style((FONT, AXIS_PX))
            .label_style((FONT, LABEL_PX + 1))
            .x_label_formatter(&tick_label)
            .draw()
            .map_err(plot_err)?;

        let mut start = vec![0.0f64; n];
        for (k, stage) in stages.iter().enumerate() {
            let c = colour(k);
            let mut bars = Vec::new();
            for (i, r) in rows.iter().enumerate() {
                let Some(&v) = r.stages_ms.get(*stage).filter(|&&v| ok(v)) else {
                    continue;
                };
                let slot = 2 * (n - 1 - i) as i32;
                let (a, b) = (slot, slot + 2);
                let mut bar = Rectangle::new([(start[i], a), (start[i] + v, b)], c.filled());
                bar.set_margin(6, 6, 0, 0);
                bars.push(bar);
                start[i] += v;
            }
            chart
                .draw_series(bars)
                .map_err(plot_err)?
                .label(*stage)
                .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], c.filled()));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FONT, LABEL_PX + 1))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(plot_err)?;
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}
