// Shadow-map access, words representation: maps rasterized by compute kernels (raster_compute),
// one R32Uint layer per map holding the bits of each texel's depth (GpuSample.layer), copied from
// the raster's storage buffer. Defines the same names as kernels/shared/maps_plain.wgsl, and reads
// the same values: a depth's bits as the fixed-function raster would store them.

alias ShadowMaps = texture_2d_array<u32>;

// Stored depth of a texel of layer `layer`: the raster reads, hybrid_build and moments use it directly.
fn layer_depth(maps: ShadowMaps, texel: vec2<i32>, layer: u32) -> f32 {
    return bitcast<f32>(textureLoad(maps, texel, i32(layer), 0).x);
}

fn map_depth(frame: GpuFrame, maps: ShadowMaps, s: GpuSample, texel: vec2<i32>) -> f32 {
    return layer_depth(maps, texel, s.layer);
}
