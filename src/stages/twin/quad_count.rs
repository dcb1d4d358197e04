//! Twin of `kernels/quad_count.wgsl`: low-quality pixels per quad.

pub fn quad_count(flags: &[u32], words_per_quad: usize, quads: usize) -> Vec<u32> {
    (0..quads)
        .map(|q| {
            flags[q * words_per_quad..(q + 1) * words_per_quad]
                .iter()
                .map(|w| w.count_ones())
                .sum()
        })
        .collect()
}
