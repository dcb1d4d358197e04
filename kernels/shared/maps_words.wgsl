// Shadow-map access, words representation: maps rasterized by compute kernels (raster_compute),
// one R32Uint layer per map holding the bits of each texel's depth (GpuSample.layer), copied from
// the raster's storage buffer. Defines the same names as kernels/shared/maps_plain.wgsl, and reads
// the same values: a depth's bits as the fixed-function raster would store them.

alias ShadowMaps = texture_2d_array<u32>;

// Stored depth of a texel of layer `layer`: the raster reads, hybrid_build and moments use it directly.
fn layer_depth(maps: ShadowMaps, texel: vec2<i32>, layer: u32) -> f32 {
    return bitcast<f32>(textureLoad(maps, texel, i32(layer), 0).x);
}

// The 2x2 block of layer `layer` whose top-left texel is t: (top-left, top-right, bottom-left,
// bottom-right), by four loads (`gather` is unused: words cannot be sampled).
fn layer_block(maps: ShadowMaps, gather: sampler, t: vec2<u32>, layer: u32, size: u32) -> vec4<f32> {
    let p = vec2<i32>(t);
    return vec4<f32>(
        layer_depth(maps, p, layer),
        layer_depth(maps, p + vec2<i32>(1, 0), layer),
        layer_depth(maps, p + vec2<i32>(0, 1), layer),
        layer_depth(maps, p + vec2<i32>(1, 1), layer),
    );
}

fn map_depth(frame: GpuFrame, maps: ShadowMaps, s: GpuSample, texel: vec2<i32>) -> f32 {
    return layer_depth(maps, texel, s.layer);
}
