//! SVG → PNG with resvg, with an embedded font so chart text is never silently dropped.

use std::sync::{Arc, OnceLock};

use resvg::tiny_skia;
use resvg::usvg::{self, fontdb};

use super::ChartError;

/// The one family every chart uses, built into the binary (the `dejavu` crate) so that text renders
/// identically on every machine, including ones with no fonts installed (GPU servers, containers).
const SANS: &str = "DejaVu Sans";

/// The embedded faces, loaded once; `sans-serif` (plotters' default) maps to them.
fn fonts() -> Arc<fontdb::Database> {
    static FONTS: OnceLock<Arc<fontdb::Database>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = fontdb::Database::new();
            db.load_font_data(dejavu::sans::regular().to_vec());
            db.load_font_data(dejavu::sans::bold().to_vec());
            db.set_sans_serif_family(SANS);
            Arc::new(db)
        })
        .clone()
}

/// Rasterises `svg` at `scale` × its size onto white, text in the embedded DejaVu Sans.
pub fn svg_to_png(svg: &str, scale: f32) -> Result<Vec<u8>, ChartError> {
    if !(scale.is_finite() && scale > 0.0) {
        return Err(ChartError::BadScale(scale));
    }
    // `font_family` covers text with no family attribute at all.
    let options = usvg::Options {
        font_family: SANS.to_string(),
        fontdb: fonts(),
        ..Default::default()
    };
    let tree = usvg::Tree::from_str(svg, &options).map_err(|e| ChartError::Svg(e.to_string()))?;
    let size = tree.size();
    let (w, h) = (
        (size.width() * scale).ceil(),
        (size.height() * scale).ceil(),
    );
    if !(1.0..=16384.0).contains(&w) || !(1.0..=16384.0).contains(&h) {
        return Err(ChartError::BadScale(scale));
    }
    let mut pixmap =
        tiny_skia::Pixmap::new(w as u32, h as u32).ok_or(ChartError::BadScale(scale))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| ChartError::Png(e.to_string()))
}
