//! Twin of `kernels/neighbourhood.wgsl`: low quality when 0 < c < 4 and the clamped 3x3
//! neighbourhood holds the same byte (background / unevaluated bytes are 0, so they differ).

pub struct Screen {
    pub width: u32,
    pub height: u32,
}

impl Screen {
    pub fn words_per_row(&self) -> u32 {
        self.width.div_ceil(4)
    }
    pub fn flag_words_per_row(&self) -> u32 {
        self.width.div_ceil(32)
    }
}

pub fn byte_at(counts: &[u32], s: &Screen, q: usize, x: i32, y: i32) -> u32 {
    let cx = x.clamp(0, s.width as i32 - 1) as u32;
    let cy = y.clamp(0, s.height as i32 - 1) as u32;
    let words = (s.height * s.words_per_row()) as usize;
    (counts[q * words + (cy * s.words_per_row() + cx / 4) as usize] >> ((cx & 3) * 8)) & 0xff
}

pub fn low_quality(counts: &[u32], s: &Screen, q: usize, x: i32, y: i32) -> bool {
    let b = byte_at(counts, s, q, x, y);
    if !(2..=4).contains(&b) {
        return false;
    }
    (-1..=1).all(|dy| (-1..=1).all(|dx| byte_at(counts, s, q, x + dx, y + dy) == b))
}

/// Flags of `quads` quads: quads × rows × flag_words_per_row.
pub fn neighbourhood(counts: &[u32], s: &Screen, quads: usize) -> Vec<u32> {
    let fwpr = s.flag_words_per_row();
    let words = (s.height * fwpr) as usize;
    let mut out = vec![0u32; quads * words];
    for q in 0..quads {
        for y in 0..s.height {
            for x in 0..s.width {
                if low_quality(counts, s, q, x as i32, y as i32) {
                    out[q * words + (y * fwpr + x / 32) as usize] |= 1 << (x % 32);
                }
            }
        }
    }
    out
}
