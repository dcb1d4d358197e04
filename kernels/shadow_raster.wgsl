// Depth-only raster of the scene from one light sample into one layer of the shadow-map array.
// The draw's instance index selects the sample, so many layers are recorded per submission.

@group(0) @binding(0) var<storage, read> samples: array<GpuSample>;

@vertex
fn vs_main(@location(0) position: vec3<f32>, @builtin(instance_index) sample: u32) -> @builtin(position) vec4<f32> {
    return samples[sample].light_from_world * vec4<f32>(position, 1.0);
}

// A kept map's rectangle drawn again (a moved mesh's, docs/reuse.md): this triangle covers the
// whole layer at the far plane and, drawn first with the depth test off inside the pass's scissor,
// clears just that rectangle; the scene's draw follows in the same pass.
@vertex
fn vs_far(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = f32((i << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(i & 2u) * 2.0 - 1.0;
    return vec4<f32>(x, y, 1.0, 1.0);
}
