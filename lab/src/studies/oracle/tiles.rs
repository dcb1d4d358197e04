//! The screen's 8×8 tiles (shade's tile) as the reference sees them: geometry pixels, penumbra
//! pixels, and which tiles are uniformly lit or dark; and a frame's squared error per tile.

/// The side of a tile in pixels: shade's tile, the unit a per-region method assigns.
pub const TILE: u32 = 8;

#[derive(Clone, Debug)]
pub struct Tiles {
    pub width: u32,
    pub height: u32,
    pub cols: u32,
    pub rows: u32,
    /// Per tile (row order): geometry pixels, and of those in penumbra (0 < V < 1).
    pub px: Vec<u32>,
    pub pen: Vec<u32>,
    /// Geometry, every pixel of it lit (V = 1) or every pixel dark (V = 0).
    pub free: Vec<bool>,
    /// Per pixel: its tile, or None outside the geometry.
    of_pixel: Vec<Option<u32>>,
}

impl Tiles {
    /// `reference` and `mask` per pixel, row order, `width` × `height`.
    pub fn of(reference: &[f32], mask: &[bool], width: u32, height: u32) -> Tiles {
        let (cols, rows) = (width.div_ceil(TILE), height.div_ceil(TILE));
        let n = (cols * rows) as usize;
        let (mut px, mut pen, mut lit, mut dark) =
            (vec![0u32; n], vec![0u32; n], vec![0u32; n], vec![0u32; n]);
        let mut of_pixel = vec![None; mask.len()];
        for (i, (&v, &geometry)) in reference.iter().zip(mask).enumerate() {
            if !geometry {
                continue;
            }
            let (x, y) = (i as u32 % width, i as u32 / width);
            let t = (y / TILE) * cols + x / TILE;
            of_pixel[i] = Some(t);
            let t = t as usize;
            px[t] += 1;
            if v >= 1.0 {
                lit[t] += 1;
            } else if v <= 0.0 {
                dark[t] += 1;
            } else {
                pen[t] += 1;
            }
        }
        let free = (0..n)
            .map(|t| px[t] > 0 && (lit[t] == px[t] || dark[t] == px[t]))
            .collect();
        Tiles {
            width,
            height,
            cols,
            rows,
            px,
            pen,
            free,
            of_pixel,
        }
    }

    /// A frame's summed squared error of V per tile, over geometry pixels.
    pub fn sse(&self, v: &[f32], reference: &[f32]) -> Vec<f64> {
        let mut out = vec![0.0; self.px.len()];
        for ((t, &a), &b) in self.of_pixel.iter().zip(v).zip(reference) {
            if let Some(t) = t {
                out[*t as usize] += (f64::from(a) - f64::from(b)).powi(2);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_of_a_small_screen() {
        // 12 × 9 pixels: 2 × 2 tiles, the right and bottom ones partial. The left half is lit
        // ground, the top-right tile dark but for one penumbra pixel, the bottom row no geometry
        // beyond the first tile's row 8.
        let (w, h) = (12u32, 9u32);
        let mut reference = vec![1.0f32; (w * h) as usize];
        let mut mask = vec![true; (w * h) as usize];
        for y in 0..8 {
            for x in 8..12 {
                reference[(y * w + x) as usize] = 0.0;
            }
        }
        reference[(3 * w + 9) as usize] = 0.5;
        for x in 0..w {
            mask[(8 * w + x) as usize] = x < 8;
        }
        let t = Tiles::of(&reference, &mask, w, h);
        assert_eq!((t.cols, t.rows), (2, 2));
        assert_eq!(t.px, [64, 32, 8, 0]);
        assert_eq!(t.pen, [0, 1, 0, 0]);
        assert_eq!(t.free, [true, false, true, false]);
        let mut v = reference.clone();
        v[(3 * w + 9) as usize] = 0.0;
        v[(8 * w + 2) as usize] = 0.5;
        v[(8 * w + 10) as usize] = 0.0; // outside the geometry: not counted
        assert_eq!(t.sse(&v, &reference), [0.0, 0.25, 0.25, 0.0]);
    }
}
