// barycentrics: which triangle each pixel sees and where in it, for per-vertex methods
// (env-pixels:at=vertex). The same camera, positions and triangle order as gbuffer.wgsl, so the
// same fragments win the depth test; drawn without an index buffer so that vertex_index / 3 is the
// triangle. One Rgba32Uint texel: (triangle + 1, bits of b1, bits of b2, 0); 0 is background and
// b0 = 1 − b1 − b2. Integer texels keep the float bits exactly.

struct GpuCamera {
    clip_from_world: mat4x4<f32>,
    eye: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: GpuCamera;
// scene::Vertex, 7 words each (position, normal, material), and the scene's index buffer.
@group(0) @binding(1) var<storage, read> scene_vertices: array<f32>;
@group(0) @binding(2) var<storage, read> scene_indices: array<u32>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    // Perspective-correct barycentrics: each corner carries its unit vector.
    @location(0) bary: vec3<f32>,
    @location(1) @interpolate(flat) triangle: u32,
}

@vertex
fn vs_main(@builtin(vertex_index) corner: u32) -> VertexOut {
    let b = scene_indices[corner] * 7u;
    let position = vec3<f32>(scene_vertices[b], scene_vertices[b + 1u], scene_vertices[b + 2u]);
    var out: VertexOut;
    out.clip = camera.clip_from_world * vec4<f32>(position, 1.0);
    let k = corner % 3u;
    out.bary = vec3<f32>(select(0.0, 1.0, k == 0u), select(0.0, 1.0, k == 1u), select(0.0, 1.0, k == 2u));
    out.triangle = corner / 3u;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<u32> {
    return vec4<u32>(in.triangle + 1u, bitcast<u32>(in.bary.y), bitcast<u32>(in.bary.z), 0u);
}
