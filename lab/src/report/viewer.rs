//! The image comparison viewer: one `.viewer` block per set of pictures compared with one
//! reference (a scene's methods, a failure scene's error maps, the per-region pictures). The block
//! holds each picture once, as plain figures grouped by item, which a page without scripts shows as
//! they are; `viewer.js`, inline in the page's head with `viewer.css`, turns each block into one view
//! (docs/compare-and-report.md, "The viewer").

use minijinja::value::{Serde, Value};
use minijinja::Environment;
use serde::Serialize;

const TEMPLATE: &str = include_str!("viewer.html");

/// The style and script every page with a viewer carries once, in its head. The script reads the
/// page only: no request, no storage (the report checks look for both).
pub const HEAD: &str = concat!(
    "<style>\n",
    include_str!("viewer.css"),
    "</style>\n<script>\n",
    include_str!("viewer.js"),
    "</script>\n"
);
#[cfg(test)]
const PARTS: [&str; 2] = [include_str!("viewer.js"), include_str!("viewer.css")];

/// One picture of an item. `name` is the layer the viewer switches by: `shaded`, `visibility`,
/// `abs_error` and `signed_error` have keys (s, v, e, d); any other name is reached with `l`.
#[derive(Serialize)]
pub struct Layer {
    pub name: String,
    pub caption: String,
    /// `data:image/png;base64,…` (only characters that need no HTML escaping).
    pub uri: String,
}

/// A method (or the reference) and its pictures, with the figures shown beside it.
#[derive(Serialize)]
pub struct Item {
    pub label: String,
    pub reference: bool,
    /// One line: maps, RMSE, time and what else the section measures.
    pub figures: String,
    pub layers: Vec<Layer>,
}

#[derive(Serialize)]
pub struct Viewer {
    /// What is compared, for a screen reader (`aria-label`).
    pub title: String,
    /// The scene the items were rendered on: chart points open the item of their scene.
    pub scene: String,
    pub items: Vec<Item>,
}

/// The viewer's block. Items of one picture each are laid out as a gallery without the script.
pub fn render(v: &Viewer) -> Result<String, minijinja::Error> {
    let mut env = Environment::new();
    env.add_template("viewer.html", TEMPLATE)?;
    let compact = v.items.iter().all(|i| i.layers.len() <= 1);
    let ctx = minijinja::context! { title => &v.title, scene => &v.scene, items => Value::from(Serde(&v.items)), compact => compact };
    env.get_template("viewer.html")?.render(ctx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_viewer_holds_each_picture_once_and_escapes_its_text() {
        let layer = |name: &str, uri: &str| Layer {
            name: name.into(),
            caption: name.into(),
            uri: uri.into(),
        };
        let v = Viewer {
            title: "images of <a>".into(),
            scene: "s&t".into(),
            items: vec![
                Item {
                    label: "reference".into(),
                    reference: true,
                    figures: String::new(),
                    layers: vec![layer("shaded", "data:image/png;base64,AA")],
                },
                Item {
                    label: "adaptive:p_m=0".into(),
                    reference: false,
                    figures: "RMSE 0.0100 · 25 maps".into(),
                    layers: vec![
                        layer("shaded", "data:image/png;base64,BB"),
                        layer("abs_error", "data:image/png;base64,CC"),
                    ],
                },
            ],
        };
        let html = render(&v).unwrap();
        assert_eq!(html.matches("<img ").count(), 3);
        assert_eq!(html.matches("data-reference").count(), 1);
        assert!(
            html.contains("data-scene=\"s&amp;t\"")
                && html.contains("aria-label=\"images of &lt;a&gt;\""),
            "{html}"
        );
        assert!(
            html.contains("<figure data-layer=\"abs_error\"><img src=\"data:image/png;base64,CC\""),
            "{html}"
        );
        assert!(
            html.contains("<p class=\"v-figures\">RMSE 0.0100 · 25 maps</p>"),
            "{html}"
        );
        assert!(
            !html.contains("compact"),
            "two layers per method: not a gallery"
        );
    }

    #[test]
    fn the_script_and_style_stay_self_contained() {
        // What the report checks refuse anywhere in a page, and what would end the script early.
        for (part, bad) in PARTS.iter().flat_map(|p| {
            [
                "http:",
                "https:",
                "url(",
                "@import",
                "<link",
                "<script",
                "</script",
                "src=",
                "href=",
                "fetch(",
                "XMLHttpRequest",
                "localStorage",
                "import(",
            ]
            .map(|b| (p, b))
        }) {
            assert!(
                !part.contains(bad),
                "viewer script or style contains {bad:?}"
            );
        }
        assert_eq!(HEAD.matches("<script>").count(), 1);
    }
}
