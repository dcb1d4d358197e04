//! The self-contained HTML page: one minijinja template, every image a data URI.

use minijinja::value::{Serde, Value};
use minijinja::Environment;
use serde::Serialize;

use super::table::Table;
use super::ReportError;

const TEMPLATE: &str = include_str!("template.html");

#[derive(Serialize)]
pub(super) struct ChartView {
    pub name: String,
    /// The chart's SVG, inline: its points' marks answer hover, focus and clicks.
    pub svg: String,
}

#[derive(Serialize)]
pub(super) struct Page<'a> {
    pub title: &'a str,
    pub settings: Vec<(String, String)>,
    pub tables: &'a [Table],
    pub charts: Vec<ChartView>,
    /// Rendered `viewer` blocks, one per reference.
    pub viewers: Vec<String>,
    pub viewer_head: &'static str,
}

/// A chart's SVG document as an element of the page: without the XML namespace (an HTML parser
/// puts `<svg>` in it anyway; the checks refuse any `http` text in a page), with a role and a
/// name for screen readers. Plotters escapes every text it writes.
pub(super) fn inline_svg(svg: &str) -> String {
    svg.replacen(" xmlns=\"http://www.w3.org/2000/svg\"", " role=\"img\"", 1)
}

/// minijinja 3 converts serde types only through the `Serde` wrapper (2.x had
/// `Value::from_serialize`). Renders with auto-escaping on (the template name ends in `.html`); only
/// what this crate wrote (the viewers, whose text the viewer template escapes; the charts' SVG,
/// escaped by plotters; the viewer's script and style) is passed through `|safe`.
pub(super) fn render(page: &Page) -> Result<String, ReportError> {
    let mut env = Environment::new();
    env.add_template("report.html", TEMPLATE)?;
    Ok(env
        .get_template("report.html")?
        .render(Value::from(Serde(page)))?)
}
