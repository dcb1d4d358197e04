// Bilinear percentage-closer tap as the comparison sampler computes it (texel centres at i + 0.5,
// clamped to the edge), from four map_depth reads: for the representations without a depth
// texture to sample (words, hybrid). `compare` is unused here.

fn map_compare_bilinear(frame: GpuFrame, maps: ShadowMaps, compare: sampler_comparison, s: GpuSample, t: vec2<f32>, reference: f32) -> f32 {
    let g = t - vec2<f32>(0.5);
    let f = fract(g);
    let t0 = vec2<i32>(floor(g));
    let last = i32(frame.map_size) - 1;
    var lit = 0.0;
    for (var k = 0; k < 4; k = k + 1) {
        let o = vec2<i32>(k & 1, k >> 1u);
        let texel = clamp(t0 + o, vec2<i32>(0), vec2<i32>(last));
        let w = select(1.0 - f.x, f.x, o.x == 1) * select(1.0 - f.y, f.y, o.y == 1);
        lit = lit + w * select(0.0, 1.0, reference <= map_depth(frame, maps, s, texel));
    }
    return lit;
}
