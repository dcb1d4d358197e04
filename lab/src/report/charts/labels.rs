//! Point labels placed so they do not overlap each other or other points: greedy, in x order,
//! the first spot around the point that is free and inside the plot.

/// Pixel box `(x0, y0, x1, y1)`.
type Box = (i32, i32, i32, i32);

fn overlaps(a: Box, b: Box) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// Width of a label in pixels at `font_px` (DejaVu Sans averages ~0.5 em per character in
/// these labels; slightly generous so boxes do not touch).
pub(super) fn text_width(text: &str, font_px: u32) -> i32 {
    (text.chars().count() as f64 * 0.52 * font_px as f64).ceil() as i32
}

/// Where a label goes: top-left corner offset from its point, and whether it sits away from
/// the point (then a leader line joins them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Spot {
    pub dx: i32,
    pub dy: i32,
    pub far: bool,
}

impl Spot {
    /// Point of the label box nearest to the point, as an offset: where a leader line ends.
    pub fn anchor(&self, width: i32, height: i32) -> (i32, i32) {
        (
            0.clamp(self.dx, self.dx + width),
            0.clamp(self.dy, self.dy + height),
        )
    }
}

/// A spot for each label, for points at `at` (pixels) with labels `widths` wide and `height`
/// tall, inside `area` (x0, y0, x1, y1). Right of the point first, then left, then rows further
/// out; never over another label or within `CLEAR` pixels of another point.
pub(super) fn place(at: &[(i32, i32)], widths: &[i32], height: i32, area: Box) -> Vec<Spot> {
    const GAP: i32 = 7;
    // Keep labels this far from other points, so none reads as belonging to a neighbour.
    const CLEAR: i32 = 12;
    let dots: Vec<Box> = at
        .iter()
        .map(|&(x, y)| (x - CLEAR, y - CLEAR, x + CLEAR, y + CLEAR))
        .collect();
    let mut labels: Vec<Box> = Vec::new();
    let mut order: Vec<usize> = (0..at.len()).collect();
    order.sort_by_key(|&i| (at[i].0, at[i].1));
    let mut out = vec![
        Spot {
            dx: GAP,
            dy: -height - 2,
            far: false
        };
        at.len()
    ];
    for i in order {
        let (w, h) = (widths[i], height);
        if w == 0 {
            continue; // no label: nothing to place
        }
        // Rows above and below the point, nearest first; right of the point before left.
        let mut candidates = Vec::new();
        for row in 0..3 {
            let (up, down) = (-h - 2 - row * (h + 2), 2 + row * (h + 2));
            candidates.extend([(GAP, up), (GAP, down), (-GAP - w, up), (-GAP - w, down)]);
        }
        let boxed = |(dx, dy): (i32, i32)| {
            (
                at[i].0 + dx,
                at[i].1 + dy,
                at[i].0 + dx + w,
                at[i].1 + dy + h,
            )
        };
        let inside = |b: Box| b.0 >= area.0 && b.1 >= area.1 && b.2 <= area.2 && b.3 <= area.3;
        let free = |b: Box| {
            !labels.iter().any(|&t| overlaps(t, b))
                && !dots
                    .iter()
                    .enumerate()
                    .any(|(j, &d)| j != i && overlaps(d, b))
        };
        let k = (0..candidates.len())
            .find(|&k| inside(boxed(candidates[k])) && free(boxed(candidates[k])))
            .or_else(|| (0..candidates.len()).find(|&k| inside(boxed(candidates[k]))))
            .unwrap_or(0);
        labels.push(boxed(candidates[k]));
        out[i] = Spot {
            dx: candidates[k].0,
            dy: candidates[k].1,
            far: k >= 4,
        };
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn close_points_get_separate_spots() {
        let at = [(100, 100), (104, 101), (300, 300)];
        let off = place(&at, &[80, 80, 40], 14, (0, 0, 1000, 1000));
        let b = |i: usize| {
            (
                at[i].0 + off[i].dx,
                at[i].1 + off[i].dy,
                at[i].0 + off[i].dx + [80, 80, 40][i],
                at[i].1 + off[i].dy + 14,
            )
        };
        assert!(!overlaps(b(0), b(1)), "{off:?}");
        assert_eq!(
            off[2],
            Spot {
                dx: 7,
                dy: -16,
                far: false
            },
            "a lone point keeps the first spot"
        );
        assert_eq!(
            Spot {
                dx: 7,
                dy: 20,
                far: true
            }
            .anchor(50, 14),
            (7, 20)
        );
        assert_eq!(
            Spot {
                dx: -57,
                dy: -16,
                far: true
            }
            .anchor(50, 14),
            (-7, -2)
        );
    }

    #[test]
    fn labels_stay_inside_the_area() {
        let off = place(&[(990, 5)], &[60], 14, (0, 0, 1000, 1000));
        let (x, y) = (990 + off[0].dx, 5 + off[0].dy);
        assert!(
            x >= 0 && x + 60 <= 1000 && y >= 0 && y + 14 <= 1000,
            "{off:?}"
        );
    }
}
