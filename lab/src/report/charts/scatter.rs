//! One scatter-chart renderer behind charts (a)–(c): grouped points, optional labels, x
//! whiskers, per-group lines and a Pareto staircase, on linear or log axes.

use std::ops::Range;

use plotters::coord::combinators::{BindKeyPoints, LogCoord, WithKeyPoints};
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::prelude::*;

use super::labels;
use super::style::{colour, plot_err, AXIS_PX, FONT, LABEL_PX, SIZE, TITLE_PX};
use super::ChartError;

pub(crate) struct Point {
    pub x: f64,
    pub y: f64,
    pub label: Option<String>,
    /// Horizontal whisker (e.g. min..max time).
    pub x_span: Option<(f64, f64)>,
    /// What the point answers in the report (its row's figures, the method it opens).
    pub hit: Option<Hit>,
}

/// A point's row: the report's viewer item it opens (label and scene) and its figures, the
/// tooltip. Drawn as a focusable mark over the point whose `<title>` reads without a script.
pub(crate) struct Hit {
    pub label: String,
    pub scene: String,
    pub text: String,
}

impl Hit {
    /// The row's setting, maps, RMSE, FLIP and time, as a tooltip says them.
    pub fn of(r: &super::ResultRow) -> Hit {
        let spread =
            if r.frame_ms_min.is_finite() && r.frame_ms_max.is_finite() && r.frame_ms_max > 0.0 {
                format!(" ({:.2}–{:.2})", r.frame_ms_min, r.frame_ms_max)
            } else {
                String::new()
            };
        let maps = if r.core.maps == 1 {
            "1 map".to_string()
        } else {
            format!("{} maps", r.core.maps)
        };
        let text = format!(
            "{} ({})\n{maps} · RMSE {:.4} · FLIP {:.4} · {:.2} ms{spread}",
            r.label(),
            r.core.scene,
            r.metrics.rmse,
            r.metrics.flip_mean,
            r.core.frame_ms
        );
        Hit {
            label: r.label(),
            scene: r.core.scene.clone(),
            text,
        }
    }
}

/// `svg` with one transparent, focusable mark per hit point (at its pixel), after everything
/// plotters drew, so they are on top. The PNG (resvg) draws nothing of them.
fn with_hits(svg: String, hits: &[((i32, i32), &Hit)]) -> String {
    let Some(end) = svg.rfind("</svg>").filter(|_| !hits.is_empty()) else {
        return svg;
    };
    let esc = |t: &str| {
        t.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
            .replace('"', "&quot;")
    };
    let mut g = String::from("<g class=\"hits\">\n");
    for ((x, y), h) in hits {
        let text = esc(&h.text);
        g += &format!(
            "<circle class=\"hit\" cx=\"{x}\" cy=\"{y}\" r=\"8\" fill=\"#000\" fill-opacity=\"0\" tabindex=\"0\" role=\"button\" data-label=\"{}\" data-scene=\"{}\" aria-label=\"{}\"><title>{text}</title></circle>\n",
            esc(&h.label),
            esc(&h.scene),
            text.replace('\n', ", ")
        );
    }
    g += "</g>\n";
    format!("{}{g}{}", &svg[..end], &svg[end..])
}

pub(crate) struct Series {
    pub name: String,
    pub points: Vec<Point>,
}

/// Adds `point` to the series called `name`, starting that series if it is new (first-seen order).
pub(crate) fn push_point(series: &mut Vec<Series>, name: String, point: Point) {
    match series.iter_mut().find(|s| s.name == name) {
        Some(s) => s.points.push(point),
        None => series.push(Series {
            name,
            points: vec![point],
        }),
    }
}

pub(crate) struct Scatter {
    pub title: String,
    pub x_desc: String,
    pub y_desc: String,
    pub series: Vec<Series>,
    /// Join each series' points in x order.
    pub connect: bool,
    /// Path drawn as the Pareto front, if any.
    pub front: Option<Vec<(f64, f64)>>,
    /// The path's legend entry.
    pub front_label: &'static str,
    /// Log axes are used only when asked *and* every value on that axis is > 0.
    pub x_log: bool,
    pub y_log: bool,
}

impl Scatter {
    fn values(&self, f: impl Fn(&Point) -> Vec<f64>) -> Vec<f64> {
        self.series
            .iter()
            .flat_map(|s| s.points.iter().flat_map(&f))
            .filter(|v| v.is_finite())
            .collect()
    }
}

/// Axis range with some air around the data; multiplicative padding on log axes. The padded ends
/// stay finite (a value near f64's largest padded to infinity once).
fn padded(values: &[f64], log: bool) -> Range<f64> {
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let finite = |v: f64| v.clamp(-f64::MAX, f64::MAX);
    if log {
        let (lo, hi) = if hi / lo < 10.0 {
            (lo / 2.0, hi * 2.0)
        } else {
            (lo / 1.4, hi * 1.4)
        };
        lo.max(f64::MIN_POSITIVE)..finite(hi)
    } else {
        let pad = if hi > lo {
            0.08 * (hi - lo)
        } else {
            lo.abs().max(1.0) * 0.1
        };
        finite(lo - pad)..finite(hi + pad)
    }
}

pub(crate) fn render(spec: &Scatter) -> Result<String, ChartError> {
    let xs = spec.values(|p| {
        let mut v = vec![p.x];
        v.extend(p.x_span.map(|(a, b)| [a, b]).into_iter().flatten());
        v
    });
    let ys = spec.values(|p| vec![p.y]);
    if xs.is_empty() || ys.is_empty() {
        return Err(ChartError::NoData("no finite point"));
    }
    let x_log = spec.x_log && xs.iter().all(|&v| v > 0.0);
    let y_log = spec.y_log && ys.iter().all(|&v| v > 0.0);
    let (xr, yr) = (padded(&xs, x_log), padded(&ys, y_log));
    match (x_log, y_log) {
        (true, true) => draw(spec, log_axis(xr), log_axis(yr)),
        (true, false) => draw(spec, log_axis(xr), yr),
        (false, true) => draw(spec, xr, log_axis(yr)),
        (false, false) => draw(spec, xr, yr),
    }
}

/// Log axis with our own ticks: plotters' log key points repeat labels and crowd light lines.
fn log_axis(r: Range<f64>) -> WithKeyPoints<LogCoord<f64>> {
    let (bold, light) = log_ticks(r.start, r.end);
    r.log_scale().with_key_points(bold).with_light_points(light)
}

/// Labelled ticks at 1-2-5 × 10^k (1 × 10^k only beyond three decades, 1..9 × 10^k when the
/// range is too narrow for two), light grid lines at 1..9 × 10^k.
/// Over more than [`MAX_DECADES`] decades the labelled ticks step by several decades and the light
/// lines go: the loops stay bounded whatever the range (f64 spans about 630 decades).
pub(crate) fn log_ticks(lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    // Exponents of finite positive ends lie in -324..=309; anything else is clamped there.
    let exponent = |v: f64, round: fn(f64) -> f64| {
        if v > 0.0 && v.is_finite() {
            round(v.log10()).clamp(-324.0, 309.0) as i32
        } else if v > 0.0 {
            309
        } else {
            -324
        }
    };
    let (k0, k1) = (exponent(lo, f64::floor), exponent(hi, f64::ceil));
    let step = ((k1 - k0) / MAX_DECADES + 1).max(1) as usize;
    let within = |mult: &[f64], step: usize| -> Vec<f64> {
        (k0..=k1)
            .step_by(step)
            .flat_map(|k| mult.iter().map(move |m| m * 10f64.powi(k)))
            .filter(|v| (lo..=hi).contains(v))
            .collect()
    };
    let all: Vec<f64> = (1..=9).map(f64::from).collect();
    if step > 1 {
        return (within(&[1.0], step), Vec::new());
    }
    let mut bold = within(
        if k1 - k0 > 3 {
            &[1.0]
        } else {
            &[1.0, 2.0, 5.0]
        },
        1,
    );
    if bold.len() < 2 {
        bold = within(&all, 1);
    }
    (bold, within(&all, 1))
}

/// The most decades a log axis labels one by one.
const MAX_DECADES: i32 = 12;

/// Short tick label: about four significant digits, no trailing zeros ("0.005", "60", "1000").
pub(crate) fn tick_label(v: &f64) -> String {
    if *v == 0.0 || !v.is_finite() {
        return "0".into();
    }
    let decimals = (3 - v.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn draw<XS, YS>(spec: &Scatter, x_spec: XS, y_spec: YS) -> Result<String, ChartError>
where
    XS: AsRangedCoord<Value = f64>,
    YS: AsRangedCoord<Value = f64>,
    XS::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    YS::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut svg = String::new();
    let hits: Vec<((i32, i32), &Hit)>;
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&spec.title, (FONT, TITLE_PX))
            .margin(16)
            .x_label_area_size(56)
            .y_label_area_size(80)
            .build_cartesian_2d(x_spec, y_spec)
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc(&spec.x_desc)
            .y_desc(&spec.y_desc)
            .axis_desc_style((FONT, AXIS_PX))
            .label_style((FONT, LABEL_PX + 1))
            .x_label_formatter(&tick_label)
            .y_label_formatter(&tick_label)
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(plot_err)?;

        if let Some(path) = &spec.front {
            let style = RGBColor(60, 60, 60).stroke_width(2);
            chart
                .draw_series(LineSeries::new(path.iter().copied(), style))
                .map_err(plot_err)?
                .label(spec.front_label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        }
        // Label spots for every labelled point of every series at once, so no two collide.
        let sorted: Vec<Vec<&Point>> = spec
            .series
            .iter()
            .map(|s| {
                let mut pts: Vec<&Point> = s
                    .points
                    .iter()
                    .filter(|p| p.x.is_finite() && p.y.is_finite())
                    .collect();
                pts.sort_by(|a, b| a.x.total_cmp(&b.x));
                pts
            })
            .collect();
        let all: Vec<&Point> = sorted.iter().flatten().copied().collect();
        let at: Vec<(i32, i32)> = all
            .iter()
            .map(|p| chart.backend_coord(&(p.x, p.y)))
            .collect();
        hits = all
            .iter()
            .zip(&at)
            .filter_map(|(p, &xy)| p.hit.as_ref().map(|h| (xy, h)))
            .collect();
        let widths: Vec<i32> = all
            .iter()
            .map(|p| labels::text_width(p.label.as_deref().unwrap_or(""), LABEL_PX))
            .collect();
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let label_h = LABEL_PX as i32 + 2;
        let mut spots = labels::place(&at, &widths, label_h, (xr.start, yr.start, xr.end, yr.end))
            .into_iter()
            .zip(widths);
        for (k, pts) in sorted.iter().enumerate() {
            let c = colour(k);
            if spec.connect && pts.len() > 1 {
                chart
                    .draw_series(LineSeries::new(
                        pts.iter().map(|p| (p.x, p.y)),
                        c.stroke_width(2),
                    ))
                    .map_err(plot_err)?;
            }
            let whiskers = pts.iter().filter_map(|p| {
                p.x_span
                    .map(|(a, b)| PathElement::new(vec![(a, p.y), (b, p.y)], c))
            });
            chart.draw_series(whiskers).map_err(plot_err)?;
            let font = (FONT, LABEL_PX).into_font().color(&BLACK);
            let placed: Vec<(labels::Spot, i32)> = spots.by_ref().take(pts.len()).collect();
            let marks = pts.iter().zip(placed).map(|(p, (spot, width))| {
                let text = Text::new(
                    p.label.clone().unwrap_or_default(),
                    (spot.dx, spot.dy),
                    font.clone(),
                );
                // A label pushed away from its point gets a thin leader line back to it.
                let labelled = p.label.as_deref().is_some_and(|l| !l.is_empty());
                let end = if spot.far && labelled {
                    spot.anchor(width, label_h)
                } else {
                    (0, 0)
                };
                let leader = PathElement::new(vec![(0, 0), end], RGBColor(150, 150, 150));
                EmptyElement::at((p.x, p.y)) + leader + Circle::new((0, 0), 5, c.filled()) + text
            });
            chart
                .draw_series(marks)
                .map_err(plot_err)?
                .label(spec.series[k].name.clone())
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, c.filled()));
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
    Ok(with_hits(svg, &hits))
}
