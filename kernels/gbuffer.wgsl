// G-buffer: world position (w = 1 on geometry, 0 on background) and the normal facing the camera
// (w = material index), one texel per screen pixel, read by every compute stage.

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
}

@fragment
fn fs_main(in: VertexOut) -> GBufferOut {
    var n = normalize(in.normal);
    // Two-sided surfaces: the shadow test wants the side the camera sees.
    if (dot(n, camera.eye.xyz - in.world) < 0.0) {
        n = -n;
    }
    var out: GBufferOut;
    out.position = vec4<f32>(in.world, 1.0);
    out.normal = vec4<f32>(n, f32(in.material));
    return out;
}
