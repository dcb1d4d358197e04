//! A 3×5 bitmap font for legend numbers, so error images carry labels without a font stack.

use image::{Rgb, RgbImage};

/// Rows of 3 bits, top to bottom; bit 2 = left column.
fn glyph(c: char) -> Option<[u8; 5]> {
    Some(match c {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        '.' => [0, 0, 0, 0, 2],
        '-' => [0, 0, 7, 0, 0],
        '+' => [0, 2, 7, 2, 0],
        ' ' => [0; 5],
        _ => return None,
    })
}

/// Horizontal advance of one glyph at `scale`, spacing included.
pub(super) fn advance(scale: u32) -> u32 {
    4 * scale
}

/// Width in pixels of `text` at `scale`.
pub(super) fn text_width(text: &str, scale: u32) -> u32 {
    (text.chars().count() as u32 * advance(scale)).saturating_sub(scale)
}

/// Draws `text` with its top-left corner at (x, y); unknown characters and pixels outside the
/// image are skipped.
pub(super) fn draw_text(
    img: &mut RgbImage,
    x: u32,
    y: u32,
    text: &str,
    scale: u32,
    colour: [u8; 3],
) {
    for (k, c) in text.chars().enumerate() {
        let Some(rows) = glyph(c) else { continue };
        let gx = x + k as u32 * advance(scale);
        for (row, bits) in rows.iter().enumerate() {
            for col in 0..3u32 {
                if bits & (4 >> col) == 0 {
                    continue;
                }
                for dy in 0..scale {
                    for dx in 0..scale {
                        let (px, py) = (gx + col * scale + dx, y + row as u32 * scale + dy);
                        if px < img.width() && py < img.height() {
                            img.put_pixel(px, py, Rgb(colour));
                        }
                    }
                }
            }
        }
    }
}
