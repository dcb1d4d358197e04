// env_vertex_interp: V per pixel from V per vertex (env-pixels:at=vertex), interpolated with the
// pixel's barycentrics in the triangle it sees (barycentrics.wgsl): V = b0·V0 + b1·V1 + b2·V2,
// times the ambient occlusion when ssao is on. Background pixels keep V = 0.

@group(0) @binding(0) var<uniform> params: GpuEnvParams;
@group(0) @binding(1) var triangle_ids: texture_2d<u32>;
@group(0) @binding(2) var<storage, read> scene_indices: array<u32>;
@group(0) @binding(3) var<storage, read> vertex_visibility: array<f32>;
@group(0) @binding(4) var<storage, read> ao: array<f32>;
@group(0) @binding(5) var<storage, read_write> visibility: array<f32>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let id = textureLoad(triangle_ids, vec2<i32>(gid.xy), 0);
    if (id.x == 0u) {
        return;
    }
    let t = (id.x - 1u) * 3u;
    let b1 = bitcast<f32>(id.y);
    let b2 = bitcast<f32>(id.z);
    let b0 = 1.0 - b1 - b2;
    let v0 = vertex_visibility[scene_indices[t]];
    let v1 = vertex_visibility[scene_indices[t + 1u]];
    let v2 = vertex_visibility[scene_indices[t + 2u]];
    var v = b0 * v0 + b1 * v1 + b2 * v2;
    let index = gid.y * params.width + gid.x;
    if (params.use_ao != 0u) {
        v = v * ao[index];
    }
    visibility[index] = v;
}
