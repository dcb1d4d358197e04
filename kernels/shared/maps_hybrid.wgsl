// Shadow-map access, hybrid representation (seed 003, docs/hybrid.md). Every map of a store lives in
// one R32Uint pool texture read as a flat array of u32 words (word a at texel (a % 4096, a / 4096)):
//   words 0 .. slots:  the address of each slot's coarse grid (GpuSample.layer is the slot);
//   coarse grid:       (map_size >> levels)² nodes, row-major;
//   node:              a depth (f32 bits; depths are >= 0, so the top bit is 0), or
//                      HYBRID_CHILDREN | the address of 4 child nodes (2x2, row-major) one level finer.
// The lookup descends from the coarse node to the first depth: full resolution only where the build
// (kernels/hybrid_build.wgsl) found a depth step.

alias ShadowMaps = texture_2d<u32>;

const HYBRID_POOL_WIDTH_LOG2: u32 = 12u;
const HYBRID_CHILDREN: u32 = 0x80000000u;
// GpuFrame.flags bits 8..9: the hybrid store's merge levels (1 or 2).
const FRAME_HYBRID_LEVELS_SHIFT: u32 = 8u;

fn hybrid_word(maps: ShadowMaps, a: u32) -> u32 {
    let column = a & ((1u << HYBRID_POOL_WIDTH_LOG2) - 1u);
    return textureLoad(maps, vec2<u32>(column, a >> HYBRID_POOL_WIDTH_LOG2), 0).x;
}

fn map_depth(frame: GpuFrame, maps: ShadowMaps, s: GpuSample, texel: vec2<i32>) -> f32 {
    let levels = (frame.flags >> FRAME_HYBRID_LEVELS_SHIFT) & 3u;
    let t = vec2<u32>(texel);
    let coarse = frame.map_size >> levels;
    let c = t >> vec2<u32>(levels);
    var node = hybrid_word(maps, hybrid_word(maps, s.layer) + c.y * coarse + c.x);
    var level = levels;
    while ((node & HYBRID_CHILDREN) != 0u && level > 0u) {
        level = level - 1u;
        let q = (t >> vec2<u32>(level)) & vec2<u32>(1u);
        node = hybrid_word(maps, (node & ~HYBRID_CHILDREN) + q.y * 2u + q.x);
    }
    return bitcast<f32>(node);
}
