// Depth-only raster of the scene from one light sample into one layer of the shadow-map array.
// The draw's instance index selects the sample, so many layers are recorded per submission.

@group(0) @binding(0) var<storage, read> samples: array<GpuSample>;

@vertex
fn vs_main(@location(0) position: vec3<f32>, @builtin(instance_index) sample: u32) -> @builtin(position) vec4<f32> {
    return samples[sample].light_from_world * vec4<f32>(position, 1.0);
}
