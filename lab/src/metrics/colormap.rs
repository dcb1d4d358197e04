//! Colour maps for error images, as piecewise-linear tables in sRGB.

/// Magma (matplotlib), sampled at t = 0, 1/8, …, 1: perceptually uniform, dark = small error.
const MAGMA: [[u8; 3]; 9] = [
    [0, 0, 4],
    [28, 16, 68],
    [79, 18, 123],
    [129, 37, 129],
    [181, 54, 122],
    [229, 80, 100],
    [251, 135, 97],
    [254, 194, 135],
    [252, 253, 191],
];

/// Diverging blue-white-red (ColorBrewer RdBu, reversed) at t = 0, 1/4, …, 1.
const BLUE_WHITE_RED: [[u8; 3]; 5] = [
    [33, 102, 172],
    [146, 197, 222],
    [247, 247, 247],
    [244, 165, 130],
    [178, 24, 43],
];

fn lerp_table(table: &[[u8; 3]], t: f32) -> [u8; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (table.len() - 1) as f32;
    let i = (x.floor() as usize).min(table.len() - 2);
    let f = x - i as f32;
    let mix = |a: u8, b: u8| (f32::from(a) + (f32::from(b) - f32::from(a)) * f).round() as u8;
    let (a, b) = (table[i], table[i + 1]);
    [mix(a[0], b[0]), mix(a[1], b[1]), mix(a[2], b[2])]
}

/// t in [0,1] (clamped) → magma colour.
pub(super) fn magma(t: f32) -> [u8; 3] {
    lerp_table(&MAGMA, t)
}

/// t in [0,1] (clamped; 0.5 = zero error) → blue-white-red colour.
pub(super) fn diverging(t: f32) -> [u8; 3] {
    lerp_table(&BLUE_WHITE_RED, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_and_middle() {
        assert_eq!(magma(0.0), MAGMA[0]);
        assert_eq!(magma(1.0), MAGMA[8]);
        assert_eq!(magma(2.0), MAGMA[8]);
        assert_eq!(diverging(0.5), [247, 247, 247]);
        assert_eq!(diverging(0.0), BLUE_WHITE_RED[0]);
        assert_eq!(magma(f32::NAN), MAGMA[0]);
    }
}
