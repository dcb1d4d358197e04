// ssao: screen-space ambient occlusion (seed 002 §2.4). Each pixel places `light_count` points of a
// fixed hemisphere kernel (radius in world units) around its G-buffer point, projects them to the
// screen and counts those behind the surface stored there within the radius; AO = 1 − that share.

struct GpuCamera {
    clip_from_world: mat4x4<f32>,
    eye: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: GpuEnvParams;
@group(0) @binding(1) var<uniform> camera: GpuCamera;
@group(0) @binding(2) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(4) var<storage, read> kernel: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> ao: array<f32>;
@group(0) @binding(6) var<storage, read_write> occluded: array<u32>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let index = gid.y * params.width + gid.x;
    let position = textureLoad(gbuffer_position, vec2<i32>(gid.xy), 0);
    if (position.w == 0.0) {
        ao[index] = 0.0;
        occluded[index] = 0u;
        return;
    }
    let p = position.xyz;
    let n = textureLoad(gbuffer_normal, vec2<i32>(gid.xy), 0).xyz;
    // Tangent frame (twin: compute::twin::ssao::frame).
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 0.0, 1.0), abs(n.x) > 0.9);
    let t = normalize(env_cross(helper, n));
    let b = env_cross(n, t);
    var count = 0u;
    for (var k = 0u; k < params.light_count; k = k + 1u) {
        let s = kernel[k].xyz * params.radius;
        let q = p + t * s.x + b * s.y + n * s.z;
        let clip = camera.clip_from_world * vec4<f32>(q, 1.0);
        if (clip.w <= 0.0) {
            continue;
        }
        let uv = vec2<f32>(clip.x / clip.w * 0.5 + 0.5, 0.5 - clip.y / clip.w * 0.5);
        let texel = floor(uv * vec2<f32>(f32(params.width), f32(params.height)));
        if (texel.x < 0.0 || texel.y < 0.0 || texel.x >= f32(params.width) || texel.y >= f32(params.height)) {
            continue;
        }
        let stored = textureLoad(gbuffer_position, vec2<i32>(texel), 0);
        if (stored.w == 0.0) {
            continue;
        }
        let eye = camera.eye.xyz;
        let in_front = length(stored.xyz - eye) < length(q - eye) - params.ray_offset;
        let near = length(stored.xyz - p) < params.radius;
        if (in_front && near) {
            count = count + 1u;
        }
    }
    occluded[index] = count;
    ao[index] = 1.0 - f32(count) / f32(max(params.light_count, 1u));
}
