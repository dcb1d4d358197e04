//! Twin of `kernels/hybrid_build.wgsl` (the merge and its index) and of `map_depth` in
//! `kernels/shared/maps_hybrid.wgsl` (the lookup), same operation order.

use crate::stages::hybrid_build::CHILDREN;
// The pool's reader is the product's too (pictures of the maps); the twin tests compare it with
// `map_depth`.
pub use crate::stages::hybrid_pool::{decode, lookup, stored_levels};

/// One 2x2 block of full texels: depths (row-major), mean, whether it merges.
#[derive(Clone, Copy, Debug, Default)]
struct Block {
    d: [f32; 4],
    mean: f32,
    flat: bool,
}

fn block_mean(a: f32, b: f32, c: f32, d: f32) -> f32 {
    ((a + b) + (c + d)) * 0.25
}

fn block_flat(d: [f32; 4], mean: f32, eps: f32) -> bool {
    d.iter().all(|x| (x - mean).abs() <= eps)
}

fn fine_block(depth: &[f32], base: u32, x: u32, y: u32, eps: f32) -> Block {
    let at = |x: u32, y: u32| depth[(y * base + x) as usize];
    let d = [at(x, y), at(x + 1, y), at(x, y + 1), at(x + 1, y + 1)];
    let mean = block_mean(d[0], d[1], d[2], d[3]);
    Block {
        d,
        mean,
        flat: block_flat(d, mean, eps),
    }
}

struct Coarse {
    child: [Block; 4],
    mean: f32,
    flat: bool,
    words: u32,
}

fn coarse_texel(depth: &[f32], base: u32, levels: u32, cx: u32, cy: u32, eps: f32) -> Coarse {
    if levels == 1 {
        let b = fine_block(depth, base, cx * 2, cy * 2, eps);
        return Coarse {
            child: [b; 4],
            mean: b.mean,
            flat: b.flat,
            words: if b.flat { 0 } else { 4 },
        };
    }
    let mut child = [Block::default(); 4];
    let mut all_flat = true;
    let mut open = 0;
    for q in 0..4u32 {
        let b = fine_block(
            depth,
            base,
            cx * 4 + (q & 1) * 2,
            cy * 4 + (q >> 1) * 2,
            eps,
        );
        child[q as usize] = b;
        all_flat &= b.flat;
        open += (!b.flat) as u32;
    }
    let m = [child[0].mean, child[1].mean, child[2].mean, child[3].mean];
    let mean = block_mean(m[0], m[1], m[2], m[3]);
    let flat = all_flat && block_flat(m, mean, eps);
    Coarse {
        child,
        mean,
        flat,
        words: if flat { 0 } else { 4 + 4 * open },
    }
}

/// The words of one map as `hybrid_build` writes them at pool address `map_base`: the coarse grid,
/// then the children in row-major coarse order (pointers are absolute pool addresses). `eps` is in
/// depth units (the setting / 65535).
pub fn build(depth: &[f32], base: u32, levels: u32, eps: f32, map_base: u32) -> Vec<u32> {
    let coarse = base >> levels;
    let cells: Vec<Coarse> = (0..coarse * coarse)
        .map(|i| coarse_texel(depth, base, levels, i % coarse, i / coarse, eps))
        .collect();
    // classify + scan_rows + scan_total: exclusive offsets in row-major order.
    let mut offsets = Vec::with_capacity(cells.len());
    let mut sum = 0u32;
    for c in &cells {
        offsets.push(sum);
        sum += c.words;
    }
    let grid = coarse * coarse;
    let mut out = vec![0u32; (grid + sum) as usize];
    // emit
    for (i, c) in cells.iter().enumerate() {
        if c.flat {
            out[i] = c.mean.to_bits();
            continue;
        }
        let first = grid + offsets[i];
        out[i] = CHILDREN | (map_base + first);
        let first = first as usize;
        if levels == 1 {
            for (k, d) in c.child[0].d.iter().enumerate() {
                out[first + k] = d.to_bits();
            }
            continue;
        }
        let mut next = first + 4;
        for (q, b) in c.child.iter().enumerate() {
            if b.flat {
                out[first + q] = b.mean.to_bits();
            } else {
                out[first + q] = CHILDREN | (map_base + next as u32);
                for (k, d) in b.d.iter().enumerate() {
                    out[next + k] = d.to_bits();
                }
                next += 4;
            }
        }
    }
    out
}

/// A pool holding one map in slot 0, laid out as the GPU lays out a freshly reset store.
pub fn single_map_pool(depth: &[f32], base: u32, levels: u32, eps: f32) -> Vec<u32> {
    let mut pool = vec![1u32];
    pool.extend(build(depth, base, levels, eps, 1));
    pool
}
