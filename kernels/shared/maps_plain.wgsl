// Shadow-map access, plain representation: one Depth32Float layer per map (GpuSample.layer).
// Every map-reading kernel reads depths only through these functions; kernels/shared/maps_words.wgsl
// defines the same names for maps rasterized by compute kernels, and maps_hybrid.wgsl for
// hybrid-resolution maps (docs/hybrid.md).

alias ShadowMaps = texture_depth_2d_array;

// Stored depth of a texel of layer `layer`: the raster reads, hybrid_build and moments use it directly.
fn layer_depth(maps: ShadowMaps, texel: vec2<i32>, layer: u32) -> f32 {
    return textureLoad(maps, texel, i32(layer), 0);
}

// The 2x2 block of layer `layer` whose top-left texel is t: (top-left, top-right, bottom-left,
// bottom-right), by one gather at the block's shared corner (`gather`: nearest, clamped; `size`: the
// layer's side).
fn layer_block(maps: ShadowMaps, gather: sampler, t: vec2<u32>, layer: u32, size: u32) -> vec4<f32> {
    let g = textureGather(maps, gather, vec2<f32>(t + 1u) / f32(size), i32(layer));
    return vec4<f32>(g.w, g.z, g.x, g.y);
}

// Stored depth of sample s's map at a texel inside the map.
fn map_depth(frame: GpuFrame, maps: ShadowMaps, s: GpuSample, texel: vec2<i32>) -> f32 {
    return layer_depth(maps, texel, s.layer);
}

// Bilinear percentage-closer tap at continuous texel coordinate t: the hardware comparison sampler
// (lit where reference <= stored, clamped to the edge).
fn map_compare_bilinear(frame: GpuFrame, maps: ShadowMaps, compare: sampler_comparison, s: GpuSample, t: vec2<f32>, reference: f32) -> f32 {
    return textureSampleCompareLevel(maps, compare, t / f32(frame.map_size), i32(s.layer), reference);
}
