//! A hybrid map pool read on the CPU: the depth a slot's map holds at a texel, and the whole map
//! decoded. The product reads it for the maps' pictures; the twin tests compare it with the GPU's
//! `map_depth` (tests/kernels.rs).

use crate::stages::hybrid_build::CHILDREN;

/// The CPU's `map_depth` (kernels/shared/maps_hybrid.wgsl, same operation order): the depth slot `slot`'s map holds at full texel (x, y), and the level it is
/// stored at (0 = full resolution, 1 = a merged 2x2 block, 2 = a merged 4x4 block).
pub fn lookup(pool: &[u32], slot: u32, map_size: u32, levels: u32, x: u32, y: u32) -> (f32, u32) {
    let coarse = map_size >> levels;
    let (cx, cy) = (x >> levels, y >> levels);
    let mut node = pool[(pool[slot as usize] + cy * coarse + cx) as usize];
    let mut level = levels;
    while node & CHILDREN != 0 && level > 0 {
        level -= 1;
        let (qx, qy) = ((x >> level) & 1, (y >> level) & 1);
        node = pool[((node & !CHILDREN) + qy * 2 + qx) as usize];
    }
    (f32::from_bits(node), level)
}

/// The full-resolution map the lookup sees (row-major): what the plain-map twins take.
pub fn decode(pool: &[u32], slot: u32, map_size: u32, levels: u32) -> Vec<f32> {
    (0..map_size * map_size)
        .map(|i| lookup(pool, slot, map_size, levels, i % map_size, i / map_size).0)
        .collect()
}

/// Per full texel, the level its depth is stored at (see [`lookup`]): for the twin's tests.
#[cfg(any(test, feature = "twins"))]
pub fn stored_levels(pool: &[u32], slot: u32, map_size: u32, levels: u32) -> Vec<u32> {
    (0..map_size * map_size)
        .map(|i| lookup(pool, slot, map_size, levels, i % map_size, i / map_size).1)
        .collect()
}
