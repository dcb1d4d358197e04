//! The self-contained HTML page: one minijinja template, every image a data URI.

use minijinja::Environment;
use minijinja::value::{Serde, Value};
use serde::Serialize;

use super::ReportError;
use super::table::Table;

const TEMPLATE: &str = include_str!("template.html");

#[derive(Serialize)]
pub(super) struct Figure {
    pub caption: String,
    /// `data:image/…;base64,…` (only characters that need no HTML escaping).
    pub uri: String,
}

#[derive(Serialize)]
pub(super) struct MethodView {
    pub label: String,
    pub tiles: Vec<Figure>,
}

#[derive(Serialize)]
pub(super) struct ChartView {
    pub name: String,
    pub uri: String,
}

#[derive(Serialize)]
pub(super) struct Page<'a> {
    pub title: &'a str,
    pub settings: Vec<(String, String)>,
    pub tables: &'a [Table],
    pub charts: Vec<ChartView>,
    pub methods: Vec<MethodView>,
}

/// minijinja 3 converts serde types only through the `Serde` wrapper (2.x had
/// `Value::from_serialize`). Renders with auto-escaping on (the template name ends in `.html`); only the data URIs,
/// which are plain base64, are passed through `|safe`.
pub(super) fn render(page: &Page) -> Result<String, ReportError> {
    let mut env = Environment::new();
    env.add_template("report.html", TEMPLATE)?;
    Ok(env
        .get_template("report.html")?
        .render(Value::from(Serde(page)))?)
}
