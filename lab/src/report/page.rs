//! The page shell of the studies' own reports (sequence, failures, environment): a self-contained
//! HTML page around rendered sections, and sections appended to a page written earlier.

use crate::{Error, Result};
use minijinja::value::{Serde, Value};
use minijinja::Environment;
use serde::Serialize;
use std::path::Path;

const PAGE: &str = include_str!("page.html");

pub(crate) use super::files::data_uri;

/// Renders one minijinja template; `name` picks the escaping (`.html`: HTML) and names errors.
pub fn render(template: &str, name: &str, ctx: &impl Serialize) -> Result<String> {
    let mut env = Environment::new();
    let err = |e: minijinja::Error| Error::io_text(format!("<{name} template>"), e.to_string());
    env.add_template(name, template).map_err(err)?;
    env.get_template(name)
        .map_err(err)?
        .render(Value::from(Serde(ctx)))
        .map_err(err)
}

/// A whole self-contained page around rendered sections; with the viewer's script and style where a
/// section holds a viewer.
pub fn page(title: &str, sections: &[String]) -> Result<String> {
    let head = if sections.iter().any(|s| s.contains("<div class=\"viewer")) {
        super::viewer::HEAD
    } else {
        ""
    };
    render(
        PAGE,
        "page.html",
        &serde_json::json!({ "title": title, "sections": sections, "viewer_head": head }),
    )
}

/// Inserts sections before `</body>` of a report page written earlier (the main job's report).
pub fn append_to_page(html: &Path, sections: &[String]) -> Result<()> {
    let text = std::fs::read_to_string(html).map_err(|e| Error::io(html, e))?;
    let merged = insert_before_body(&text, sections).ok_or_else(|| {
        Error::io_text(
            html.display().to_string(),
            "no </body> to insert the sections before".into(),
        )
    })?;
    // One file of an existing set: replaced through a temporary name, the rest of the set kept.
    let dir = html.parent().unwrap_or(Path::new("."));
    let name = html
        .file_name()
        .map(|f| f.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.tmp"));
    std::fs::write(&tmp, merged).map_err(|e| Error::io(&tmp, e))?;
    std::fs::rename(&tmp, html).map_err(|e| Error::io(html, e))
}

/// `text` with the sections before its last `</body>`; `None` when it has none.
pub fn insert_before_body(text: &str, sections: &[String]) -> Option<String> {
    let at = text.rfind("</body>")?;
    Some(format!(
        "{}{}\n{}",
        &text[..at],
        sections.concat(),
        &text[at..]
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sections_go_before_the_last_body_tag() {
        let page = "<html><body><p>x</p></body></html>";
        assert_eq!(
            insert_before_body(page, &["<s>1</s>".into(), "<s>2</s>".into()]).unwrap(),
            "<html><body><p>x</p><s>1</s><s>2</s>\n</body></html>"
        );
        assert_eq!(insert_before_body("<html>", &[]), None);
    }
}
