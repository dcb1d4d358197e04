//! Twin of compact.wgsl `main` (scope = local, without the footprints of `main_rects`): each item
//! goes on to its quad's four children (split and in or beside the quad's penumbra), becomes a
//! probe (split, uniform) or adds its count to V's integer sum.

use super::neighbourhood::Screen;
use crate::stages::adaptive_buffers::NO_SPLIT;

#[derive(Debug, Default)]
pub struct CompactOut {
    /// The next level's items, in item order (the GPU appends them in any order).
    pub next_items: Vec<(u32, u32)>,
    /// (pixel, first child, lit), in item order.
    pub probes: Vec<(u32, u32, bool)>,
}

/// `counts`: the level's comparison maps (reproject_count `list`); `split_base`: subdivide's.
pub fn compact(
    s: &Screen,
    level: u32,
    max_level: u32,
    items: &[(u32, u32)],
    counts: &[u32],
    split_base: &[u32],
    visibility_fixed: &mut [u32],
) -> CompactOut {
    let wpr = s.words_per_row();
    let words = (s.height * wpr) as usize;
    let byte = |q: u32, x: u32, y: u32| {
        (counts[q as usize * words + (y * wpr + x / 4) as usize] >> ((x & 3) * 8)) & 0xff
    };
    let mut out = CompactOut::default();
    for &(p, q) in items {
        let (x, y) = (p % s.width, p / s.width);
        let c = byte(q, x, y) - 1;
        let base = split_base[q as usize];
        if base == NO_SPLIT {
            visibility_fixed[p as usize] += c << (2 * (max_level - level));
        } else if (c > 0 && c < 4) || beside_penumbra(s, &byte, q, x, y) {
            out.next_items.extend((0..4).map(|child| (p, base + child)));
        } else {
            out.probes.push((p, base, c == 4));
        }
    }
    out
}

/// The halo: whether any 3x3 neighbour of (x, y) evaluated quad `q` and found it partly lit (its
/// count byte is 2..=4, c = 1..3).
fn beside_penumbra(
    s: &Screen,
    byte: &dyn Fn(u32, u32, u32) -> u32,
    q: u32,
    x: u32,
    y: u32,
) -> bool {
    (-1..=1).any(|dy: i32| {
        (-1..=1).any(|dx: i32| {
            let (nx, ny) = (x as i32 + dx, y as i32 + dy);
            nx >= 0
                && ny >= 0
                && nx < s.width as i32
                && ny < s.height as i32
                && (2..=4).contains(&byte(q, nx as u32, ny as u32))
        })
    })
}
