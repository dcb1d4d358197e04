// env_count: env-adaptive's counting. For every (pixel, active cell), the rays to the cell's four
// corners above p's tangent plane; a pixel whose corners disagree (some lit, some blocked) adds one
// to the cell's count with an atomic (docs/environment.md §2). Corner directions come precomputed
// on the finest lattice, (finest_width + 1) × (finest_height + 1) points. Only every
// count_stride-th pixel in x and y is counted (the rays of counting dominate a frame otherwise).

@group(0) @binding(0) var<uniform> params: GpuEnvParams;
@group(0) @binding(1) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(2) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(3) var<storage, read> corners: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> cells: array<GpuEnvCell>;
@group(0) @binding(5) var<storage, read_write> counts: array<atomic<u32>>;

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    // Every count_stride-th pixel in x and y (docs/environment.md §2: the criterion's sample).
    let stride = max(params.count_stride, 1u);
    let columns = (params.width + stride - 1u) / stride;
    let rows = (params.height + stride - 1u) / stride;
    let cell_index = gid.y;
    if (gid.x >= columns * rows || cell_index >= params.cell_count) {
        return;
    }
    let xy = vec2<i32>(i32((gid.x % columns) * stride), i32((gid.x / columns) * stride));
    let position = textureLoad(gbuffer_position, xy, 0);
    if (position.w == 0.0) {
        return;
    }
    let n = textureLoad(gbuffer_normal, xy, 0).xyz;
    let o = env_origin(position.xyz, n, params.ray_offset);
    let cell = cells[cell_index];
    var valid = 0u;
    var lit = 0u;
    for (var c = 0u; c < 4u; c = c + 1u) {
        let i = cell.i + (c & 1u) * cell.size;
        let j = cell.j + (c >> 1u) * cell.size;
        let d = corners[j * (params.finest_width + 1u) + i].xyz;
        if (env_dot(n, d) <= 0.0) {
            continue;
        }
        valid = valid + 1u;
        if (!env_occluded(o, d, params.t_max)) {
            lit = lit + 1u;
        }
    }
    if (lit > 0u && lit < valid) {
        atomicAdd(&counts[cell_index], 1u);
    }
}
