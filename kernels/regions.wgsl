// regions: each screen region's sample count and texel need, from what the frame measures
// (docs/regions.md). `measure` runs pcss's blocker search on the centre map at every geometry
// pixel and keeps, per region (REGION side square of pixels), the most samples any pixel needs,
// the finest texel it needs and the box of its receivers. `classify` gives each 8x8 geometry tile
// its region's class (the first ladder entry at or above that count), appends it to the class's
// tile list (shade's format) and merges the texel need and box into the class.

struct RegionsParams {
    regions_x: u32,
    region: u32,
    ladder_len: u32,
    max_n: u32,
    // Pixels of penumbra one step of the grid may span (docs/regions.md, "Samples").
    step: f32,
    blocker_taps: u32,
    max_radius: f32,
    section_words: u32,
    light_u: f32,
    light_v: f32,
    max_tiles: u32,
    pad: u32,
    // The classes' samples per side, ascending; entry c is ladder[c / 4][c % 4].
    ladder: array<vec4<u32>, 4>,
}

// Words per region and per class: the count (samples per side for a region, tiles for a class),
// the finest texel (tangent units per texel, as ordered bits), then the receivers' box (min xyz,
// max xyz, as ordered bits).
const REGION_WORDS: u32 = 8u;

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> params: RegionsParams;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(5) var shadow_maps: ShadowMaps;
@group(0) @binding(6) var<storage, read_write> regions: array<atomic<u32>>;
@group(0) @binding(7) var<storage, read> tile_list: array<u32>;
@group(0) @binding(8) var<storage, read_write> classes: array<atomic<u32>>;
@group(0) @binding(9) var<storage, read_write> class_tiles: array<atomic<u32>>;

// A float as a u32 whose unsigned order is the float's order (atomicMin/Max on floats).
fn ordered(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

fn midpoint(i: u32, n: u32, r: f32) -> f32 {
    return -r + 2.0 * r * (f32(i) + 0.5) / f32(n);
}

// World distance to neighbour pixel + d on the screen, or -1 where it is off screen or background.
fn gap(p: vec3<f32>, pixel: vec2<i32>, d: vec2<i32>) -> f32 {
    let q = pixel + d;
    if (q.x < 0 || q.y < 0 || q.x >= i32(frame.width) || q.y >= i32(frame.height)) {
        return -1.0;
    }
    let other = textureLoad(gbuffer_position, q, 0);
    return select(-1.0, length(other.xyz - p), other.w != 0.0);
}

// The nearer of two gaps that exist (the other side of a silhouette is far), or -1.
fn nearer(a: f32, b: f32) -> f32 {
    if (a < 0.0) {
        return b;
    }
    if (b < 0.0) {
        return a;
    }
    return min(a, b);
}

// The pixel's world footprint: the larger of its across and down gaps (0 for a lone pixel).
fn footprint(p: vec3<f32>, pixel: vec2<i32>) -> f32 {
    let fx = nearer(gap(p, pixel, vec2<i32>(-1, 0)), gap(p, pixel, vec2<i32>(1, 0)));
    let fy = nearer(gap(p, pixel, vec2<i32>(0, -1)), gap(p, pixel, vec2<i32>(0, 1)));
    return max(max(fx, fy), 0.0);
}

@compute @workgroup_size(8, 8, 1)
fn measure(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    let pixel = vec2<i32>(gid.xy);
    let s = samples[0];
    let px = map_pixel(frame, s, gbuffer_position, gbuffer_normal, pixel);
    if (!px.geometry) {
        return;
    }
    let f = footprint(px.position, pixel);
    // Lit by the whole light (outside the map, or no blocker found) and below the light's plane
    // alike: one sample tells them, at the pixel's own footprint.
    var n = 1u;
    var width = 0.0;
    var z_r = 1.0;
    if (px.lookup.kind == LOOKUP_COMPARE) {
        // pcss's blocker search (kernels/pcss.wgsl), over the map region through which p sees the light.
        z_r = px.lookup.depth_limit;
        let slope = slope_per_texel(frame, s, px.position, px.normal);
        let near = s.depth_lin_a / s.depth_lin_b;
        let per_angle = 1.0 / s.texel_angle;
        let light = vec2<f32>(params.light_u, params.light_v) * 0.5;
        let search = min(light * max(z_r - near, 0.0) / (z_r * near) * per_angle, vec2<f32>(params.max_radius));
        let size = f32(frame.map_size);
        var blocker_sum = 0.0;
        var blockers = 0u;
        var taps = 0u;
        let nb = params.blocker_taps;
        for (var j = 0u; j < nb; j = j + 1u) {
            for (var i = 0u; i < nb; i = i + 1u) {
                let o = vec2<f32>(midpoint(i, nb, search.x), midpoint(j, nb, search.y));
                let texel = floor(px.uv + o);
                if (texel.x < 0.0 || texel.y < 0.0 || texel.x >= size || texel.y >= size) {
                    continue;
                }
                taps = taps + 1u;
                let stored = map_depth(frame, shadow_maps, s, vec2<i32>(texel));
                if (!depth_passes(s, z_r - length(o) * slope, stored)) {
                    blocker_sum = blocker_sum + s.depth_lin_a / (stored + s.depth_lin_b);
                    blockers = blockers + 1u;
                }
            }
        }
        // Blockers over part of the search: a penumbra. Over all of it: the umbra, one sample.
        if (blockers > 0u && blockers < taps) {
            let z_b = blocker_sum / f32(blockers);
            // The penumbra's full width at the receiver, by similar triangles.
            width = max(params.light_u, params.light_v) * max(z_r - z_b, 0.0) / z_b;
            let pixels = select(0.0, width / f, f > 0.0);
            n = clamp(u32(ceil(min(pixels / params.step, f32(params.max_n)))), 1u, params.max_n);
        }
    }
    // A texel may be as wide as the pixel, or as one step of the grid across the penumbra.
    let texel = max(f, width / f32(n)) / z_r;
    let region = (gid.y / params.region) * params.regions_x + gid.x / params.region;
    let base = region * REGION_WORDS;
    atomicMax(&regions[base], n);
    if (texel > 0.0) {
        atomicMin(&regions[base + 1u], ordered(texel));
    }
    let p = px.position;
    atomicMin(&regions[base + 2u], ordered(p.x));
    atomicMin(&regions[base + 3u], ordered(p.y));
    atomicMin(&regions[base + 4u], ordered(p.z));
    atomicMax(&regions[base + 5u], ordered(p.x));
    atomicMax(&regions[base + 6u], ordered(p.y));
    atomicMax(&regions[base + 7u], ordered(p.z));
}

// Class of `n` samples per side: the first ladder entry at or above it (the last one at most).
fn class_of(n: u32) -> u32 {
    var c = 0u;
    loop {
        if (c + 1u >= params.ladder_len || params.ladder[c / 4u][c % 4u] >= n) {
            break;
        }
        c = c + 1u;
    }
    return c;
}

@compute @workgroup_size(64, 1, 1)
fn classify(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= tile_list[0] || gid.x >= params.max_tiles) {
        return;
    }
    let tile = tile_list[TILE_LIST_HEADER + gid.x];
    let tiles_x = (frame.width + 7u) / 8u;
    let x = (tile % tiles_x) * 8u;
    let y = (tile / tiles_x) * 8u;
    let region = (y / params.region) * params.regions_x + x / params.region;
    let base = region * REGION_WORDS;
    let c = class_of(atomicLoad(&regions[base]));
    let section = c * params.section_words;
    let slot = atomicAdd(&class_tiles[section], 1u);
    atomicStore(&class_tiles[section + TILE_LIST_HEADER + slot], tile);
    let cb = c * REGION_WORDS;
    atomicAdd(&classes[cb], 1u);
    atomicMin(&classes[cb + 1u], atomicLoad(&regions[base + 1u]));
    for (var k = 2u; k < 5u; k = k + 1u) {
        atomicMin(&classes[cb + k], atomicLoad(&regions[base + k]));
        atomicMax(&classes[cb + k + 3u], atomicLoad(&regions[base + k + 3u]));
    }
}
