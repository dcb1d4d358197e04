//! The per-region method's pictures in a compare report (docs/regions.md): for each `regions` row,
//! the samples per side and the texel density of every tile, from its untimed pictures frame.

use crate::methods::Method;
use crate::report::page::data_uri;
use crate::Result;
use std::path::Path;

/// Whether a compare of `methods` draws the regions' pictures (a pictures frame per method).
pub fn wants_pictures(methods: &[Method]) -> bool {
    methods.iter().any(|m| m.name() == "regions")
}

/// Appends to `html` one section with the pictures of every `regions` method of the compare, in the
/// report's viewer: one item per method, its pictures as layers.
pub fn append(
    html: &Path,
    methods: &[Method],
    pictures: &[Vec<(String, image::RgbImage)>],
) -> Result<()> {
    use crate::report::viewer::{render, Item, Layer, Viewer};
    let mut items = Vec::new();
    for (m, drawn) in methods
        .iter()
        .zip(pictures)
        .filter(|(m, _)| m.name() == "regions")
    {
        let mut layers = Vec::new();
        for (caption, img) in drawn {
            let mut png = Vec::new();
            img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
                .map_err(|e| crate::Error::io_text(caption.clone(), e.to_string()))?;
            let name = caption.strip_suffix(".png").unwrap_or(caption).to_string();
            let shown = match name.as_str() {
                "region_samples" => "samples per side",
                "region_texels" => "texel density",
                other => other,
            };
            layers.push(Layer {
                caption: shown.to_string(),
                name,
                uri: data_uri("image/png", &png),
            });
        }
        if !layers.is_empty() {
            items.push(Item {
                label: m.label(),
                reference: false,
                figures: String::new(),
                layers,
            });
        }
    }
    if items.is_empty() {
        return Ok(());
    }
    let scene = String::new();
    let viewer = render(&Viewer {
        title: "per-region decisions of every regions method".into(),
        scene,
        items,
    })
    .map_err(|e| crate::Error::io_text("<regions viewer>".into(), e.to_string()))?;
    let h = format!(
        "<section id=\"regions\"><h2>Per-region decisions</h2>\n<p>Each 8×8 tile's samples per side \
         (dark: 1, bright: the frame's most) and its texel density, pixel footprint over the world size of \
         its class's texel (blue: a texel spans several pixels, white: one per pixel, red: several texels \
         per pixel); docs/regions.md. In the viewer, l switches the picture and a click fixes the zoom.</p>\n{viewer}</section>\n"
    );
    crate::report::page::append_to_page(html, &[h])
}
