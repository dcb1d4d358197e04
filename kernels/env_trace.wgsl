// env_trace: seed 002's pixel lights. For every G-buffer pixel (`main`) or every mesh vertex
// (`vertex`, the seed's per-vertex variant), one shadow ray per light towards its direction through
// the scene's BVH; V = Σ power·cos·vis / Σ power·cos over the lights above the point's tangent plane
// (docs/environment.md §2). `blocked` counts the occluded rays (the twins' exact check).
// Lights come in chunks (one dispatch each, params.first_light..+light_count): lavapipe returned
// wrong counts for one dispatch of 1024 or more lights per pixel (twin test), 512 were exact.

@group(0) @binding(0) var<uniform> params: GpuEnvParams;
@group(0) @binding(1) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(2) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(3) var<storage, read> lights: array<GpuEnvLight>;
// V per pixel (`main`).
@group(0) @binding(4) var<storage, read_write> visibility: array<f32>;
// Blocked rays per pixel (`main`) or per vertex (`vertex`).
@group(0) @binding(5) var<storage, read_write> blocked: array<u32>;
@group(0) @binding(6) var<storage, read> ao: array<f32>;
// Running sums (Σ power·cos·vis, Σ power·cos) between chunks of lights, per pixel or per vertex.
@group(0) @binding(7) var<storage, read_write> sums: array<vec2<f32>>;
// The scene's vertex buffer (scene::Vertex: position, normal, material; 7 words each) (`vertex`).
@group(0) @binding(8) var<storage, read> scene_vertices: array<f32>;
// V per vertex (`vertex`).
@group(0) @binding(9) var<storage, read_write> vertex_visibility: array<f32>;

struct EnvSums {
    num: f32,
    den: f32,
    blocked: u32,
}

// This chunk's lights from origin o over normal n, added to the sums of the chunks before.
fn trace_chunk(o: vec3<f32>, n: vec3<f32>, index: u32) -> EnvSums {
    var s = EnvSums(0.0, 0.0, 0u);
    if (params.first_light > 0u) {
        s = EnvSums(sums[index].x, sums[index].y, blocked[index]);
    }
    for (var k = params.first_light; k < params.first_light + params.light_count; k = k + 1u) {
        let l = lights[k].direction;
        let c = env_dot(n, l.xyz);
        if (c <= 0.0) {
            continue;
        }
        let w = l.w * c;
        s.den = s.den + w;
        if (env_occluded(o, l.xyz, params.t_max)) {
            s.blocked = s.blocked + 1u;
        } else {
            s.num = s.num + w;
        }
    }
    blocked[index] = s.blocked;
    if (params.final_chunk == 0u) {
        sums[index] = vec2<f32>(s.num, s.den);
    }
    return s;
}

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
    let s = trace_chunk(env_origin(position.xyz, n, params.ray_offset), n, index);
    if (params.final_chunk == 0u) {
        return;
    }
    var v = select(0.0, s.num / s.den, s.den > 0.0);
    if (params.use_ao != 0u) {
        v = v * ao[index];
    }
    visibility[index] = v;
}

// The seed's variant: the same sum at every mesh vertex (its position, its smooth normal as the
// hemisphere's axis, the origin offset along it); env_vertex_interp spreads it over the pixels.
@compute @workgroup_size(64, 1, 1)
fn vertex(@builtin(global_invocation_id) gid: vec3<u32>) {
    let index = gid.x;
    if (index >= params.vertex_count) {
        return;
    }
    let b = index * 7u;
    let p = vec3<f32>(scene_vertices[b], scene_vertices[b + 1u], scene_vertices[b + 2u]);
    let n = vec3<f32>(scene_vertices[b + 3u], scene_vertices[b + 4u], scene_vertices[b + 5u]);
    let s = trace_chunk(env_origin(p, n, params.ray_offset), n, index);
    if (params.final_chunk != 0u) {
        vertex_visibility[index] = select(0.0, s.num / s.den, s.den > 0.0);
    }
}
