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

/// Appends to `html` one section with the pictures of each `regions` method of the compare.
pub fn append(html: &Path, methods: &[Method], pictures: &[Vec<(String, image::RgbImage)>]) -> Result<()> {
    let esc = |t: &str| t.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;");
    let mut h = String::from(
        "<section id=\"regions\"><h2>Per-region decisions</h2>\n<p>Each 8×8 tile's samples per side \
         (dark: 1, bright: the frame's most) and its texel density, pixel footprint over the world size of \
         its class's texel (blue: a texel spans several pixels, white: one per pixel, red: several texels \
         per pixel); docs/regions.md.</p>\n",
    );
    let mut any = false;
    for (m, drawn) in methods.iter().zip(pictures).filter(|(m, _)| m.name() == "regions") {
        h += &format!("<h3>{}</h3>\n<div class=\"gallery\">", esc(&m.label()));
        for (caption, img) in drawn {
            let mut png = Vec::new();
            img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).map_err(|e| crate::Error::io_text(caption.clone(), e.to_string()))?;
            h += &format!("<figure><img src=\"{}\" width=\"384\" alt=\"{}\"><figcaption>{}</figcaption></figure>", data_uri("image/png", &png), esc(caption), esc(caption));
            any = true;
        }
        h += "</div>\n";
    }
    h += "</section>\n";
    if any {
        crate::report::page::append_to_page(html, &[h])?;
    }
    Ok(())
}
