//! SVG → PNG with resvg, with fonts resolved so chart text is not silently dropped.

use std::sync::{Arc, OnceLock};

use resvg::tiny_skia;
use resvg::usvg::{self, fontdb};

use super::ChartError;

/// The family generic `sans-serif` (plotters' default) resolves to; fontdb's own default
/// ("Arial") is usually absent on Linux, and unresolved text is dropped without an error.
const SANS: &str = "DejaVu Sans";

/// System fonts, loaded once (a scan takes tens of ms), and the family `sans-serif` maps to.
/// `None` when no font face exists at all.
fn fonts() -> Option<(Arc<fontdb::Database>, String)> {
    static FONTS: OnceLock<Option<(Arc<fontdb::Database>, String)>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = fontdb::Database::new();
            db.load_system_fonts();
            let has_sans = db
                .faces()
                .any(|f| f.families.iter().any(|(name, _)| name == SANS));
            // Without DejaVu Sans take any installed family: some font beats no text.
            let family = if has_sans {
                SANS.to_string()
            } else {
                db.faces()
                    .find_map(|f| f.families.first())
                    .map(|(name, _)| name.clone())?
            };
            db.set_sans_serif_family(family.clone());
            Some((Arc::new(db), family))
        })
        .clone()
}

/// Rasterises `svg` at `scale` × its size onto white. Errors when no font is installed
/// (text would vanish) rather than returning a chart without labels.
pub fn svg_to_png(svg: &str, scale: f32) -> Result<Vec<u8>, ChartError> {
    if !(scale.is_finite() && scale > 0.0) {
        return Err(ChartError::BadScale(scale));
    }
    let (fontdb, font_family) = fonts().ok_or(ChartError::NoFonts)?;
    // `font_family` covers text with no family attribute at all.
    let options = usvg::Options {
        font_family,
        fontdb,
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
