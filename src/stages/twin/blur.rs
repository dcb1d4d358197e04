//! Twin of `kernels/blur.wgsl`: one pass along x (`horizontal`) or y, taps added in index order.

/// One separable pass over `layers` planes of `size`² vec4s; edges clamped.
pub fn blur(
    source: &[[f32; 4]],
    size: u32,
    layers: u32,
    radius: u32,
    horizontal: bool,
) -> Vec<[f32; 4]> {
    let (n, r) = (size as i32, radius as i32);
    let plane = (size * size) as usize;
    let mut out = vec![[0.0f32; 4]; plane * layers as usize];
    for l in 0..layers as usize {
        for y in 0..n {
            for x in 0..n {
                let mut sum = [0.0f32; 4];
                for k in -r..=r {
                    let (sx, sy) = if horizontal {
                        ((x + k).clamp(0, n - 1), y)
                    } else {
                        (x, (y + k).clamp(0, n - 1))
                    };
                    let v = source[l * plane + (sy * n + sx) as usize];
                    for c in 0..4 {
                        sum[c] += v[c];
                    }
                }
                out[l * plane + (y * n + x) as usize] = sum.map(|v| v / (2 * r + 1) as f32);
            }
        }
    }
    out
}
