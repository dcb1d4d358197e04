// G-buffer, one texel per screen pixel: world position (w = 1 on geometry, 0 on background), the
// geometric (flat, per-triangle) normal facing the camera (w = material index), which every shadow
// test uses, and the interpolated smooth normal, which only shading uses. The shadow tests need the
// true surface: a facet that faces away from a light point blocks it, whatever the smooth normal says.

struct GpuCamera {
    clip_from_world: mat4x4<f32>,
    eye: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: GpuCamera;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) material: u32,
}

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>, @location(2) material: u32) -> VertexOut {
    var out: VertexOut;
    out.clip = camera.clip_from_world * vec4<f32>(position, 1.0);
    out.world = position;
    out.normal = normal;
    out.material = material;
    return out;
}

struct GBufferOut {
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) shading_normal: vec4<f32>,
}

@fragment
fn fs_main(in: VertexOut) -> GBufferOut {
    let to_eye = camera.eye.xyz - in.world;
    // Screen-space derivatives of the position span the triangle's plane (helper pixels of a quad
    // interpolate the same triangle), so their cross product is the flat normal.
    var n = normalize(cross(dpdx(in.world), dpdy(in.world)));
    // Two-sided surfaces: the shadow test wants the side the camera sees.
    if (dot(n, to_eye) < 0.0) {
        n = -n;
    }
    var smooth_n = normalize(in.normal);
    if (dot(smooth_n, n) < 0.0) {
        smooth_n = -smooth_n;
    }
    var out: GBufferOut;
    out.position = vec4<f32>(in.world, 1.0);
    out.normal = vec4<f32>(n, f32(in.material));
    out.shading_normal = vec4<f32>(smooth_n, 0.0);
    return out;
}
