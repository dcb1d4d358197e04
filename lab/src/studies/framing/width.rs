//! The penumbra's width on screen, in pixels, from a reference visibility image.
//!
//! Across a penumbra V runs from 0 to 1; where its screen gradient is |∇V| per pixel, a full
//! transition at that slope spans 1/|∇V| pixels. The width is the median of 1/|∇V| over the
//! penumbra pixels (0.05 < V < 0.95) whose four neighbours are geometry too, so silhouettes and
//! the screen's edge do not enter. Central differences; a flat neighbourhood (|∇V| < 1e-6) is skipped.

/// Median penumbra width in pixels, and how many pixels it was taken over; None without penumbra.
pub fn penumbra_width_px(
    values: &[f32],
    geometry: &[bool],
    width: u32,
    height: u32,
) -> Option<(f64, usize)> {
    let (w, h) = (width as usize, height as usize);
    let at = |x: usize, y: usize| y * w + x;
    let mut widths: Vec<f64> = Vec::new();
    for y in 1..h.saturating_sub(1) {
        for x in 1..w.saturating_sub(1) {
            let i = at(x, y);
            let v = values[i] as f64;
            if !geometry[i] || !(0.05..=0.95).contains(&v) {
                continue;
            }
            let n = [at(x - 1, y), at(x + 1, y), at(x, y - 1), at(x, y + 1)];
            if n.iter().any(|&j| !geometry[j]) {
                continue;
            }
            let gx = (values[n[1]] as f64 - values[n[0]] as f64) / 2.0;
            let gy = (values[n[3]] as f64 - values[n[2]] as f64) / 2.0;
            let g = (gx * gx + gy * gy).sqrt();
            if g >= 1e-6 {
                widths.push(1.0 / g);
            }
        }
    }
    if widths.is_empty() {
        return None;
    }
    widths.sort_by(f64::total_cmp);
    let m = widths.len();
    let median = if m % 2 == 1 {
        widths[m / 2]
    } else {
        (widths[m / 2 - 1] + widths[m / 2]) / 2.0
    };
    Some((median, m))
}

#[cfg(test)]
mod tests {
    use super::penumbra_width_px;

    /// A linear ramp from 0 to 1 over `span` pixels, at any orientation, has width `span`.
    fn ramp(span: f64, angle: f64, size: u32) -> Vec<f32> {
        let (c, s) = (angle.cos(), angle.sin());
        (0..size * size)
            .map(|i| {
                let (x, y) = (
                    (i % size) as f64 - size as f64 / 2.0,
                    (i / size) as f64 - size as f64 / 2.0,
                );
                ((x * c + y * s) / span + 0.5).clamp(0.0, 1.0) as f32
            })
            .collect()
    }

    #[test]
    fn a_linear_ramp_has_its_span_as_width() {
        for (span, angle) in [(8.0, 0.0), (20.0, 0.3), (40.0, 1.1)] {
            let v = ramp(span, angle, 128);
            let geometry = vec![true; v.len()];
            let (w, n) = penumbra_width_px(&v, &geometry, 128, 128).unwrap();
            assert!(
                (w - span).abs() < 1e-3 * span,
                "span {span} angle {angle}: width {w} over {n} px"
            );
        }
    }

    #[test]
    fn a_hard_edge_or_flat_image_has_no_penumbra() {
        let hard: Vec<f32> = (0..64 * 64)
            .map(|i| if i % 64 < 32 { 0.0 } else { 1.0 })
            .collect();
        assert_eq!(
            penumbra_width_px(&hard, &vec![true; hard.len()], 64, 64),
            None
        );
        let flat = vec![0.5f32; 64 * 64];
        assert_eq!(
            penumbra_width_px(&flat, &vec![true; flat.len()], 64, 64),
            None
        );
    }

    #[test]
    fn background_neighbours_are_excluded() {
        let v = ramp(10.0, 0.0, 64);
        let geometry = vec![false; v.len()];
        assert_eq!(penumbra_width_px(&v, &geometry, 64, 64), None);
    }
}
