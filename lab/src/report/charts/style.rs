//! Shared look: size, fonts, palette, and the plotters error conversion.

use plotters::style::RGBColor;

use super::ChartError;

pub(crate) const SIZE: (u32, u32) = (960, 640);
/// Generic family; `svg_to_png` maps it to DejaVu Sans, browsers to their default sans.
pub(crate) const FONT: &str = "sans-serif";
pub(crate) const TITLE_PX: u32 = 24;
pub(crate) const AXIS_PX: u32 = 18;
pub(crate) const LABEL_PX: u32 = 13;

/// Tableau 10, then the light halves of Tableau 20: a frame has a dozen stages, and a repeated
/// colour would merge two of them in the stage chart.
const PALETTE: [(u8, u8, u8); 20] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
    (174, 199, 232),
    (255, 187, 120),
    (152, 223, 138),
    (255, 152, 150),
    (197, 176, 213),
    (196, 156, 148),
    (247, 182, 210),
    (199, 199, 199),
    (219, 219, 141),
    (158, 218, 229),
];

pub(crate) fn colour(i: usize) -> RGBColor {
    let (r, g, b) = PALETTE[i % PALETTE.len()];
    RGBColor(r, g, b)
}

pub(crate) fn plot_err(e: impl std::fmt::Display) -> ChartError {
    ChartError::Plot(e.to_string())
}

/// Name for a group of rows: the given key, prefixed with the scene when rows span scenes.
pub(crate) fn with_scene(multi_scene: bool, scene: &str, key: &str) -> String {
    if multi_scene {
        format!("{scene}: {key}")
    } else {
        key.to_string()
    }
}

/// True when the rows come from more than one scene.
pub(crate) fn spans_scenes<'a>(mut rows: impl Iterator<Item = &'a super::ResultRow>) -> bool {
    let Some(first) = rows.next() else {
        return false;
    };
    rows.any(|r| r.core.scene != first.core.scene)
}
