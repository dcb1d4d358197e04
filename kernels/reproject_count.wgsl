// reproject_count: c_q(p) in 0..4, the number of quad q's corner samples that light pixel p,
// stored as c + 1 in one byte per pixel (4 per word) of q's comparison map.
//  main: every pixel x every active quad, from the cached lattice masks (scope = global);
//  list: the compacted (pixel, quad) items only, testing the corner maps directly (scope = local).

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> level: GpuLevel;
@group(0) @binding(2) var<storage, read> quads: array<GpuQuad>;
@group(0) @binding(3) var<storage, read> masks: array<u32>;
@group(0) @binding(4) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(5) var<storage, read_write> counts: array<u32>;

@group(0) @binding(6) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(7) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(8) var maps_a: texture_depth_2d_array;
@group(0) @binding(9) var maps_b: texture_depth_2d_array;
@group(0) @binding(10) var<storage, read> items: array<vec2<u32>>;
@group(0) @binding(11) var<storage, read_write> counts_atomic: array<atomic<u32>>;
@group(0) @binding(12) var<storage, read_write> consulted: array<atomic<u32>>;
@group(0) @binding(13) var<storage, read> item_total: array<u32>;

fn mask_bit(pixel: u32, k: u32) -> u32 {
    return (masks[pixel * MASK_WORDS + k / 32u] >> (k % 32u)) & 1u;
}

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(workgroup_id) wg: vec3<u32>) {
    let words = frame.height * level.words_per_row;
    if (gid.x >= words || wg.y >= level.quad_count) {
        return;
    }
    let q = quads[level.first_quad + wg.y];
    let y = gid.x / level.words_per_row;
    let wx = gid.x % level.words_per_row;
    var packed = 0u;
    for (var b = 0u; b < 4u; b = b + 1u) {
        let x = wx * 4u + b;
        if (x < frame.width) {
            if (textureLoad(gbuffer_position, vec2<i32>(i32(x), i32(y)), 0).w != 0.0) {
                let p = y * frame.width + x;
                let c = mask_bit(p, quad_corner(q, 0u)) + mask_bit(p, quad_corner(q, 1u))
                    + mask_bit(p, quad_corner(q, 2u)) + mask_bit(p, quad_corner(q, 3u));
                packed = packed | ((c + 1u) << (b * 8u));
            }
        }
    }
    counts[wg.y * words + gid.x] = packed;
}

fn lit_lattice(k: u32, position: vec3<f32>, normal: vec3<f32>) -> u32 {
    let s = samples[k];
    let lookup = shadow_lookup(frame, s, position, normal);
    var stored: f32;
    if (s.array == 0u) {
        stored = textureLoad(maps_a, lookup.texel, i32(s.layer), 0);
    } else {
        stored = textureLoad(maps_b, lookup.texel, i32(s.layer), 0);
    }
    return shadow_compare(s, lookup, stored);
}

@compute @workgroup_size(64, 1, 1)
fn list(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= item_total[0]) {
        return;
    }
    let item = items[gid.x];
    let p = item.x;
    let q = quads[item.y];
    let pixel = vec2<i32>(i32(p % frame.width), i32(p / frame.width));
    let position = textureLoad(gbuffer_position, pixel, 0).xyz;
    let normal = textureLoad(gbuffer_normal, pixel, 0).xyz;
    var c = 0u;
    for (var corner = 0u; corner < 4u; corner = corner + 1u) {
        let k = quad_corner(q, corner);
        c = c + lit_lattice(k, position, normal);
        atomicOr(&consulted[p * MASK_WORDS + k / 32u], 1u << (k % 32u));
    }
    let words = frame.height * level.words_per_row;
    let x = p % frame.width;
    let y = p / frame.width;
    atomicOr(&counts_atomic[item.y * words + y * level.words_per_row + x / 4u], (c + 1u) << ((x & 3u) * 8u));
}
