// Environment prelude (env_* kernels and ssao): WGSL twins of the Rust Gpu* structs of
// src/gpu/structs.rs and the BVH ray test, written like src/render/bvh.rs operation for operation.

struct GpuBvhNode {
    min: vec3<f32>,
    left_first: u32,
    max: vec3<f32>,
    count: u32,
}

struct GpuTriangle {
    v0: vec4<f32>,
    e1: vec4<f32>,
    e2: vec4<f32>,
}

struct GpuEnvLight {
    direction: vec4<f32>,
}

struct GpuEnvParams {
    width: u32,
    height: u32,
    light_count: u32,
    cell_count: u32,
    ray_offset: f32,
    t_max: f32,
    finest_width: u32,
    finest_height: u32,
    max_level: u32,
    p_m: u32,
    contrast: f32,
    min_share: f32,
    total_power: f32,
    use_ao: u32,
    radius: f32,
    count_stride: u32,
    first_light: u32,
    final_chunk: u32,
    vertex_count: u32,
    pad1: u32,
}

struct GpuEnvCell {
    i: u32,
    j: u32,
    size: u32,
    level: u32,
}

const BVH_STACK: u32 = 32u;

fn env_min(a: f32, b: f32) -> f32 {
    return select(b, a, a < b);
}

fn env_max(a: f32, b: f32) -> f32 {
    return select(b, a, a > b);
}

fn env_slab(node: GpuBvhNode, o: vec3<f32>, inv: vec3<f32>, t_max: f32) -> bool {
    var t0 = 0.0;
    var t1 = t_max;
    for (var a = 0u; a < 3u; a = a + 1u) {
        let ta = (node.min[a] - o[a]) * inv[a];
        let tb = (node.max[a] - o[a]) * inv[a];
        t0 = env_max(t0, env_min(ta, tb));
        t1 = env_min(t1, env_max(ta, tb));
    }
    return t0 <= t1;
}

fn env_cross(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

fn env_dot(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// Möller–Trumbore, two-sided, edges closed.
fn env_hit(t: GpuTriangle, o: vec3<f32>, d: vec3<f32>, t_max: f32) -> bool {
    let p = env_cross(d, t.e2.xyz);
    let det = env_dot(t.e1.xyz, p);
    if (abs(det) < 1e-20) {
        return false;
    }
    let inv = 1.0 / det;
    let s = o - t.v0.xyz;
    let u = env_dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) {
        return false;
    }
    let q = env_cross(s, t.e1.xyz);
    let v = env_dot(d, q) * inv;
    if (v < 0.0 || u + v > 1.0) {
        return false;
    }
    let dist = env_dot(t.e2.xyz, q) * inv;
    return dist > 0.0 && dist < t_max;
}

// The scene's BVH: every env kernel that casts rays binds these two (bindings 20 and 21).
@group(0) @binding(20) var<storage, read> bvh_nodes: array<GpuBvhNode>;
@group(0) @binding(21) var<storage, read> bvh_triangles: array<GpuTriangle>;

// Any triangle at t ∈ (0, t_max) along o + t·d? (twin: Bvh::occluded)
fn env_occluded(o: vec3<f32>, d: vec3<f32>, t_max: f32) -> bool {
    let inv = vec3<f32>(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
    var stack: array<u32, 32>;
    var top = 1u;
    stack[0] = 0u;
    loop {
        if (top == 0u) {
            break;
        }
        top = top - 1u;
        let node = bvh_nodes[stack[top]];
        if (!env_slab(node, o, inv, t_max)) {
            continue;
        }
        if (node.count == 0u) {
            stack[top] = node.left_first;
            stack[top + 1u] = node.left_first + 1u;
            top = top + 2u;
            continue;
        }
        for (var k = node.left_first; k < node.left_first + node.count; k = k + 1u) {
            if (env_hit(bvh_triangles[k], o, d, t_max)) {
                return true;
            }
        }
    }
    return false;
}

// The ray origin of a G-buffer point: offset along the normal, towards the lit side.
fn env_origin(p: vec3<f32>, n: vec3<f32>, offset: f32) -> vec3<f32> {
    return p + n * offset;
}
