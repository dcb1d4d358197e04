// truth_trace: the reference's own integrator at a list of surface points (docs/certify.md §2).
// One workgroup per point; its 64 invocations share the point's light samples (sample k goes to
// invocation k mod 64) and add their lit samples, rays and ties into the point's counts.
//
// Written operation for operation like the lab's CPU reference (lab/src/reference/visibility.rs,
// emitter.rs, sampling.rs, tracer.rs), its twin: the same stratified samples from the same
// per-pixel SplitMix64 stream (64-bit words as two u32), the same light-kind mapping, ray offset,
// LIGHT_END_EPS and tangent-plane rule, and the same watertight, two-sided, closed triangle test
// (Woop, Benthin & Wald 2013) on the triangles' own vertices. A count is exact wherever f32
// arithmetic is: an edge function that is exactly 0 in f32 is a tie the CPU settles in f64, which
// WGSL need not have, so such rays are counted (`ties`) rather than hidden.

// The light and the samples (src/gpu/structs.rs has the Rust twins of these four structs).
struct GpuTruthParams {
    // Rectangle, disk or sphere centre.
    center: vec4<f32>,
    // Rectangle: edge_u; sun: the unit direction towards it.
    edge_u: vec4<f32>,
    // Rectangle: edge_v.
    edge_v: vec4<f32>,
    // Rectangle and disk: the unit emission normal.
    light_normal: vec4<f32>,
    kind: u32,
    mode: u32,
    // Continuous mode: samples per side, and 1/m as the CPU rounds it.
    m: u32,
    inv_m: f32,
    count: u32,
    seed_lo: u32,
    seed_hi: u32,
    ray_offset: f32,
    point_s: f32,
    point_t: f32,
    // 1 − LIGHT_END_EPS in f32: shadow rays stop short of the light.
    end_factor: f32,
    // Disk and sphere: the radius; sun: tan(α/2).
    radius: f32,
    // Sun: how far its rays go.
    reach: f32,
    // The dispatch's first point.
    first: u32,
    pad1: u32,
    pad2: u32,
}

// A surface point: the G-buffer's position and normal at `pixel`, whose index seeds its samples.
struct GpuTruthPoint {
    position: vec3<f32>,
    pixel: u32,
    normal: vec3<f32>,
    pad: u32,
}

// Per point: samples that reach the light, rays traced, rays a tie in f32 decided.
struct GpuTruthCount {
    lit: u32,
    rays: u32,
    ties: u32,
    pad: u32,
}

struct GpuTruthTriangle {
    v0: vec4<f32>,
    v1: vec4<f32>,
    v2: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: GpuTruthParams;
@group(0) @binding(1) var<storage, read> points: array<GpuTruthPoint>;
@group(0) @binding(2) var<storage, read_write> counts: array<GpuTruthCount>;
// The BVH's triangles in leaf order, as their three vertices (the environment's store v0 and two
// edges: an edge rounded in f32 is not the edge the neighbouring triangle shares).
@group(0) @binding(3) var<storage, read> truth_triangles: array<GpuTruthTriangle>;

const TRUTH_GROUP: u32 = 64u;
const KIND_RECT: u32 = 0u;
const KIND_DISK: u32 = 1u;
const KIND_SUN: u32 = 2u;
const KIND_SPHERE: u32 = 3u;
const MODE_CONTINUOUS: u32 = 0u;
const MODE_LATTICE: u32 = 1u;
const FRAC_PI_4: f32 = 0.7853981633974483;
// 1 + 2γ(3), γ(n) = nε/(1 − nε), ε = 2^-24: the box test's far distance padded so that rounding
// never culls a box the ray touches (Ize 2013; pbrt's robust slab test).
const SLAB_PAD: f32 = 1.0000004;

var<workgroup> group_lit: atomic<u32>;
var<workgroup> group_rays: atomic<u32>;
var<workgroup> group_ties: atomic<u32>;

// 64-bit words as (lo, hi).
fn add64(a: vec2<u32>, b: vec2<u32>) -> vec2<u32> {
    let lo = a.x + b.x;
    return vec2<u32>(lo, a.y + b.y + select(0u, 1u, lo < a.x));
}

// The full 64-bit product of two u32, from 16-bit halves.
fn mul32(a: u32, b: u32) -> vec2<u32> {
    let a0 = a & 0xffffu;
    let a1 = a >> 16u;
    let b0 = b & 0xffffu;
    let b1 = b >> 16u;
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let p10 = a1 * b0;
    let p11 = a1 * b1;
    let mid = (p00 >> 16u) + (p01 & 0xffffu) + (p10 & 0xffffu);
    return vec2<u32>((p00 & 0xffffu) | (mid << 16u), p11 + (p01 >> 16u) + (p10 >> 16u) + (mid >> 16u));
}

// a · b mod 2^64.
fn mul64(a: vec2<u32>, b: vec2<u32>) -> vec2<u32> {
    let low = mul32(a.x, b.x);
    return vec2<u32>(low.x, low.y + a.x * b.y + a.y * b.x);
}

// a >> n for 0 < n < 32.
fn shr64(a: vec2<u32>, n: u32) -> vec2<u32> {
    return vec2<u32>((a.x >> n) | (a.y << (32u - n)), a.y >> n);
}

const GOLDEN: vec2<u32> = vec2<u32>(0x7f4a7c15u, 0x9e3779b9u);

// SplitMix64's finaliser (sampling::splitmix64).
fn splitmix64(z0: vec2<u32>) -> vec2<u32> {
    var z = add64(z0, GOLDEN);
    z = mul64(z ^ shr64(z, 30u), vec2<u32>(0x1ce4e5b9u, 0xbf58476du));
    z = mul64(z ^ shr64(z, 27u), vec2<u32>(0x133111ebu, 0x94d049bbu));
    return z ^ shr64(z, 31u);
}

// Draw `i` (from 1) of the pixel's stream `state`: PixelRng adds GOLDEN before each draw, so the
// i-th is splitmix64(state + i · GOLDEN) and any sample's draws are reached directly.
fn draw_f32(state: vec2<u32>, i: u32) -> f32 {
    let word = splitmix64(add64(state, mul64(vec2<u32>(i, 0u), GOLDEN)));
    // The top 24 bits: exact in f32, never 1.
    return f32(word.y >> 8u) * (1.0 / 16777216.0);
}

// Unit-square sample k of the point (sampling::for_each_unit_sample, in its order).
fn unit_sample(state: vec2<u32>, k: u32) -> vec2<f32> {
    if (params.mode == MODE_CONTINUOUS) {
        let a = k % params.m;
        let b = k / params.m;
        let s = (f32(a) + draw_f32(state, 2u * k + 1u)) * params.inv_m;
        let t = (f32(b) + draw_f32(state, 2u * k + 2u)) * params.inv_m;
        return vec2<f32>(s, t);
    }
    if (params.mode == MODE_LATTICE) {
        return vec2<f32>(f32(k % 17u) / 16.0, f32(k / 17u) / 16.0);
    }
    return vec2<f32>(params.point_s, params.point_t);
}

fn dot3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// glam's normalize_or_zero: times the reciprocal length, zero where that is not finite and positive.
fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let rcp = 1.0 / sqrt(dot3(v, v));
    // rcp ≤ 3.4e38 is false for +inf and NaN.
    if (rcp > 0.0 && rcp <= 3.4028235e38) {
        return v * rcp;
    }
    return vec3<f32>(0.0);
}

fn normalize3(v: vec3<f32>) -> vec3<f32> {
    return v * (1.0 / sqrt(dot3(v, v)));
}

// The concentric map of the unit square onto the unit disk (scene::emitter::concentric).
fn concentric(st: vec2<f32>) -> vec2<f32> {
    let a = 2.0 * st.x - 1.0;
    let b = 2.0 * st.y - 1.0;
    if (a == 0.0 && b == 0.0) {
        return vec2<f32>(0.0);
    }
    if (abs(a) > abs(b)) {
        let phi = FRAC_PI_4 * (b / a);
        return vec2<f32>(a * cos(phi), a * sin(phi));
    }
    let phi = 2.0 * FRAC_PI_4 - FRAC_PI_4 * (a / b);
    return vec2<f32>(b * cos(phi), b * sin(phi));
}

struct Basis {
    u: vec3<f32>,
    v: vec3<f32>,
}

// Two unit vectors across the unit n (emitter::basis, Duff et al. 2017).
fn basis(n: vec3<f32>) -> Basis {
    // copysign(1, n.z): −0 counts as negative.
    let sign = select(1.0, -1.0, (bitcast<u32>(n.z) & 0x80000000u) != 0u);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return Basis(vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), vec3<f32>(b, sign + n.y * n.y * a, -n.y));
}

// A ray's answer: occluded, and whether a tie in f32 decided it.
struct Occlusion {
    blocked: bool,
    tie: bool,
}

// The ray's permuted axes (kx, ky, kz), its shear and origin: WatertightRay in tracer.rs.
struct Ray {
    org: vec3<f32>,
    dir: vec3<f32>,
    kx: u32,
    ky: u32,
    kz: u32,
    shear: vec3<f32>,
}

fn make_ray(org: vec3<f32>, dir: vec3<f32>) -> Ray {
    let a = abs(dir);
    var kz = 2u;
    if (a.x >= a.y && a.x >= a.z) {
        kz = 0u;
    } else if (a.y >= a.z) {
        kz = 1u;
    }
    let kx = (kz + 1u) % 3u;
    let ky = (kz + 2u) % 3u;
    return Ray(org, dir, kx, ky, kz, vec3<f32>(dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]));
}

// The distance to the triangle in (0, t_max), or -1; `tie` when an edge function that decides
// the answer is exactly 0 in f32.
struct TriangleHit {
    t: f32,
    tie: bool,
}

fn triangle_hit(ray: Ray, tri: GpuTruthTriangle, t_max: f32) -> TriangleHit {
    let s = ray.shear;
    let a = tri.v0.xyz - ray.org;
    let b = tri.v1.xyz - ray.org;
    let c = tri.v2.xyz - ray.org;
    let ax = a[ray.kx] - s.x * a[ray.kz];
    let ay = a[ray.ky] - s.y * a[ray.kz];
    let bx = b[ray.kx] - s.x * b[ray.kz];
    let by = b[ray.ky] - s.y * b[ray.kz];
    let cx = c[ray.kx] - s.x * c[ray.kz];
    let cy = c[ray.ky] - s.y * c[ray.kz];
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    // A zero edge function: the CPU recomputes all three in f64, which may decide otherwise.
    let tie = u == 0.0 || v == 0.0 || w == 0.0;
    let negative = u < 0.0 || v < 0.0 || w < 0.0;
    let positive = u > 0.0 || v > 0.0 || w > 0.0;
    // Two-sided, closed: outside only when strictly outside some edge and inside another.
    if (negative && positive) {
        return TriangleHit(-1.0, tie);
    }
    let det = u + v + w;
    if (det == 0.0) {
        return TriangleHit(-1.0, tie);
    }
    let t = (u * (s.z * a[ray.kz]) + v * (s.z * b[ray.kz]) + w * (s.z * c[ray.kz])) / det;
    if (t > 0.0 && t < t_max) {
        return TriangleHit(t, tie);
    }
    return TriangleHit(-1.0, tie);
}

// Does the ray meet the node's box at t ∈ [0, t_max]? Conservative: an axis the ray runs along
// (`inv` 0 there) constrains nothing but the origin, and the far distance is padded against
// rounding.
fn slab(node: GpuBvhNode, o: vec3<f32>, inv: vec3<f32>, along: vec3<bool>, t_max: f32) -> bool {
    var t0 = 0.0;
    var t1 = t_max;
    for (var k = 0u; k < 3u; k = k + 1u) {
        if (along[k]) {
            if (o[k] < node.min[k] || o[k] > node.max[k]) {
                return false;
            }
            continue;
        }
        let ta = (node.min[k] - o[k]) * inv[k];
        let tb = (node.max[k] - o[k]) * inv[k];
        t0 = max(t0, min(ta, tb));
        t1 = min(t1, max(ta, tb));
    }
    return t0 <= t1 * SLAB_PAD;
}

// Any triangle at t ∈ (0, t_max) along org + t·dir (Tracer::occluded). A hit that no tie decided
// ends the search; a ray whose answer rests on a tie (a tied test hit, or a tied test missed and
// nothing else hit) is answered as the f32 test says, and counted.
fn occluded(org: vec3<f32>, dir: vec3<f32>, t_max: f32) -> Occlusion {
    if (!(t_max > 0.0) || (dir.x == 0.0 && dir.y == 0.0 && dir.z == 0.0)) {
        return Occlusion(false, false);
    }
    let ray = make_ray(org, dir);
    // The box test's reciprocals, once per ray.
    let along = dir == vec3<f32>(0.0);
    let inv = select(vec3<f32>(1.0) / dir, vec3<f32>(0.0), along);
    var tie = false;
    var tied_hit = false;
    var stack: array<u32, 32>;
    var top = 1u;
    stack[0] = 0u;
    loop {
        if (top == 0u) {
            break;
        }
        top = top - 1u;
        let node = bvh_nodes[stack[top]];
        if (!slab(node, org, inv, along, t_max)) {
            continue;
        }
        if (node.count == 0u) {
            stack[top] = node.left_first;
            stack[top + 1u] = node.left_first + 1u;
            top = top + 2u;
            continue;
        }
        for (var k = node.left_first; k < node.left_first + node.count; k = k + 1u) {
            let h = triangle_hit(ray, truth_triangles[k], t_max);
            if (h.t >= 0.0 && !h.tie) {
                return Occlusion(true, false);
            }
            tie = tie || h.tie;
            tied_hit = tied_hit || h.t >= 0.0;
        }
    }
    return Occlusion(tied_hit, tie);
}

// One sample's answer: lit (1 or 0), a ray traced (1 or 0), a ray a tie decided (1 or 0).
struct SampleResult {
    lit: u32,
    ray: u32,
    tie: u32,
}

// Shadow ray from `origin` along the unit `dir` to `dist` (blocked only where dist > 0).
fn shadow_ray(origin: vec3<f32>, dir: vec3<f32>, dist: f32) -> SampleResult {
    if (!(dist > 0.0)) {
        return SampleResult(1u, 0u, 0u);
    }
    let o = occluded(origin, dir, dist * params.end_factor);
    return SampleResult(select(1u, 0u, o.blocked), 1u, select(0u, 1u, o.tie));
}

// The rectangle (visibility::visibility_of): y on the light, the origin offset towards y's side.
fn rect_sample(p: vec3<f32>, normal: vec3<f32>, st: vec2<f32>) -> SampleResult {
    let y = params.center.xyz + (st.x - 0.5) * params.edge_u.xyz + (st.y - 0.5) * params.edge_v.xyz;
    let cos_y = dot3(normal, y - p);
    if (cos_y <= 0.0) {
        return SampleResult(0u, 0u, 0u);
    }
    let origin = p + normal * (params.ray_offset * sign(cos_y));
    let seg = y - origin;
    let dist = sqrt(dot3(seg, seg));
    return shadow_ray(origin, seg / dist, dist);
}

// The other kinds (emitter::emitter_visibility): a disk of directions around `axis` of radius
// `spread`, ending on the disk, far away (the sun) or on the sphere's near surface.
struct Across {
    axis: vec3<f32>,
    spread: f32,
    frame: Basis,
}

fn emitter_sample(p: vec3<f32>, normal: vec3<f32>, origin: vec3<f32>, across: Across, st: vec2<f32>) -> SampleResult {
    let q = concentric(st);
    let off = (across.frame.u * q.x + across.frame.v * q.y) * across.spread;
    if (params.kind == KIND_DISK) {
        let y = params.center.xyz + off;
        if (dot3(normal, y - p) <= 0.0) {
            return SampleResult(0u, 0u, 0u);
        }
        let seg = y - origin;
        return shadow_ray(origin, normalize_or_zero(seg), sqrt(dot3(seg, seg)));
    }
    let w = normalize3(across.axis + off);
    if (params.kind == KIND_SUN) {
        if (dot3(normal, w) <= 0.0) {
            return SampleResult(0u, 0u, 0u);
        }
        return shadow_ray(origin, w, params.reach);
    }
    let r = params.radius;
    let to_c = params.center.xyz - p;
    let b = dot3(w, to_c);
    let disc = max(b * b - (dot3(to_c, to_c) - r * r), 0.0);
    let y = p + w * (b - sqrt(disc));
    if (dot3(normal, y - p) <= 0.0) {
        return SampleResult(0u, 0u, 0u);
    }
    let seg = y - origin;
    return shadow_ray(origin, normalize_or_zero(seg), sqrt(dot3(seg, seg)));
}

fn sample_count() -> u32 {
    if (params.mode == MODE_CONTINUOUS) {
        return params.m * params.m;
    }
    if (params.mode == MODE_LATTICE) {
        return 289u;
    }
    return 1u;
}

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let local = wid.y * groups.x + wid.x;
    let index = params.first + local;
    if (lid == 0u) {
        atomicStore(&group_lit, 0u);
        atomicStore(&group_rays, 0u);
        atomicStore(&group_ties, 0u);
    }
    workgroupBarrier();
    if (local < params.count) {
        var lit = 0u;
        var rays = 0u;
        var ties = 0u;
        let point = points[index];
        let p = point.position;
        let normal = normalize_or_zero(point.normal);
        // A point that cannot be placed or oriented traces nothing (V = 0), as on the CPU.
        let placed = normal.x != 0.0 || normal.y != 0.0 || normal.z != 0.0;
        var usable = placed;
        var across = Across(vec3<f32>(0.0), 0.0, Basis(vec3<f32>(0.0), vec3<f32>(0.0)));
        if (params.kind == KIND_RECT || params.kind == KIND_DISK) {
            // On or behind the light's plane: unlit.
            usable = usable && dot3(p - params.center.xyz, params.light_normal.xyz) > 0.0;
            across = Across(params.light_normal.xyz, params.radius, basis(params.light_normal.xyz));
        } else if (params.kind == KIND_SUN) {
            across = Across(params.edge_u.xyz, params.radius, basis(params.edge_u.xyz));
        } else {
            let to_c = params.center.xyz - p;
            let d2 = dot3(to_c, to_c);
            let r2 = params.radius * params.radius;
            // Inside the emitter: unlit.
            usable = usable && d2 > r2;
            let axis = to_c / sqrt(d2);
            across = Across(axis, params.radius / sqrt(d2 - r2), basis(axis));
        }
        if (usable) {
            let origin = p + normal * params.ray_offset;
            let state = splitmix64(vec2<u32>(params.seed_lo, params.seed_hi) ^ splitmix64(vec2<u32>(point.pixel, 0u)));
            let n = sample_count();
            for (var k = lid; k < n; k = k + TRUTH_GROUP) {
                let st = unit_sample(state, k);
                var r: SampleResult;
                if (params.kind == KIND_RECT) {
                    r = rect_sample(p, normal, st);
                } else {
                    r = emitter_sample(p, normal, origin, across, st);
                }
                lit = lit + r.lit;
                rays = rays + r.ray;
                ties = ties + r.tie;
            }
        }
        atomicAdd(&group_lit, lit);
        atomicAdd(&group_rays, rays);
        atomicAdd(&group_ties, ties);
    }
    workgroupBarrier();
    if (lid == 0u && local < params.count) {
        counts[index] = GpuTruthCount(atomicLoad(&group_lit), atomicLoad(&group_rays), atomicLoad(&group_ties), 0u);
    }
}
