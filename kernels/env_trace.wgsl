// env_trace: seed 002's pixel lights. For every G-buffer pixel, one shadow ray per light towards its
// direction through the scene's BVH; V = Σ power·cos·vis / Σ power·cos over the lights above p's
// tangent plane (docs/environment.md §2). `blocked` counts the occluded rays (the twins' exact check).
// Lights come in chunks (one dispatch each, params.first_light..+light_count): lavapipe returned
// wrong counts for one dispatch of 1024 or more lights per pixel (twin test), 512 were exact.

@group(0) @binding(0) var<uniform> params: GpuEnvParams;
@group(0) @binding(1) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(2) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(3) var<storage, read> lights: array<GpuEnvLight>;
@group(0) @binding(4) var<storage, read_write> visibility: array<f32>;
@group(0) @binding(5) var<storage, read_write> blocked: array<u32>;
@group(0) @binding(6) var<storage, read> ao: array<f32>;
// Running sums (Σ power·cos·vis, Σ power·cos) between chunks of lights.
@group(0) @binding(7) var<storage, read_write> sums: array<vec2<f32>>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let index = gid.y * params.width + gid.x;
    let position = textureLoad(gbuffer_position, vec2<i32>(gid.xy), 0);
    if (position.w == 0.0) {
        return;
    }
    let n = textureLoad(gbuffer_normal, vec2<i32>(gid.xy), 0).xyz;
    let o = env_origin(position.xyz, n, params.ray_offset);
    var num = 0.0;
    var den = 0.0;
    var count = 0u;
    if (params.first_light > 0u) {
        num = sums[index].x;
        den = sums[index].y;
        count = blocked[index];
    }
    for (var k = params.first_light; k < params.first_light + params.light_count; k = k + 1u) {
        let l = lights[k].direction;
        let c = env_dot(n, l.xyz);
        if (c <= 0.0) {
            continue;
        }
        let w = l.w * c;
        den = den + w;
        if (env_occluded(o, l.xyz, params.t_max)) {
            count = count + 1u;
        } else {
            num = num + w;
        }
    }
    blocked[index] = count;
    if (params.final_chunk == 0u) {
        sums[index] = vec2<f32>(num, den);
        return;
    }
    var v = select(0.0, num / den, den > 0.0);
    if (params.use_ao != 0u) {
        v = v * ao[index];
    }
    visibility[index] = v;
}
