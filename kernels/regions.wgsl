// regions: each screen region's samples per side and texel need, from what the frame measures
// (docs/regions.md). `measure` runs pcss's blocker search on the centre map at every geometry
// pixel and keeps per region (a square of `region` pixels) its geometry and penumbra pixels, the
// finest footprint and the narrowest penumbra (both over the receiver's depth) and the box of its
// receivers. `total` sums the regions' weights P^0.4 A^0.6 for the target's scale. `classify`
// gives each 8x8 geometry tile its region's samples per side, n = k (P/A)^0.2, and class (the
// first ladder entry at or above n), appends it to the class's tile list (shade's format) and
// merges the texel need and the box into the class.

struct RegionsParams {
    regions_x: u32,
    region: u32,
    ladder_len: u32,
    max_n: u32,
    // The frame's RMSE of V to meet (docs/regions.md, "Samples").
    rmse_target: f32,
    blocker_taps: u32,
    max_radius: f32,
    section_words: u32,
    light_u: f32,
    light_v: f32,
    max_tiles: u32,
    region_count: u32,
    // The classes' samples per side, ascending; entry c is ladder[c / 4][c % 4].
    ladder: array<vec4<u32>, 4>,
}

// Words per region: geometry pixels, penumbra pixels, the finest footprint and the narrowest
// penumbra over depth (ordered bits), then the receivers' box (min xyz, max xyz, ordered bits).
const REGION_WORDS: u32 = 10u;
// Words per class: tiles, the finest texel (tangent units per texel, ordered bits), the box.
const CLASS_WORDS: u32 = 8u;
// The weights' sum is kept in fixed point, this many units per 1.
const WEIGHT_SCALE: f32 = 16.0;
// Sampling error per penumbra pixel with n samples per side: (1/√12) n^-SAMPLING_ORDER.
const SAMPLING_ORDER: f32 = 1.5;

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
// [Σ over regions of WEIGHT_SCALE · P^0.4 A^0.6, Σ A (the frame's geometry pixels)].
@group(0) @binding(10) var<storage, read_write> totals: array<atomic<u32>>;

// A float as a u32 whose unsigned order is the float's order (atomicMin/Max on floats).
fn ordered(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

// The float of `ordered` bits.
fn unordered(k: u32) -> f32 {
    return bitcast<f32>(select(~k, k & 0x7fffffffu, (k & 0x80000000u) != 0u));
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
    let region = (gid.y / params.region) * params.regions_x + gid.x / params.region;
    let base = region * REGION_WORDS;
    atomicAdd(&regions[base], 1u);
    let f = footprint(px.position, pixel);
    // Lit by the whole light (outside the map, or no blocker found), in the umbra (every filter
    // tap blocked) or below the light's plane: one sample tells them.
    if (px.lookup.kind == LOOKUP_COMPARE) {
        // pcss's blocker search (kernels/pcss.wgsl), over the map region through which p sees the light.
        let z_r = px.lookup.depth_limit;
        let slope = slope_per_texel(frame, s, px.position, px.normal);
        let near = s.depth_lin_a / s.depth_lin_b;
        let per_angle = 1.0 / s.texel_angle;
        let light = vec2<f32>(params.light_u, params.light_v) * 0.5;
        let search = min(light * max(z_r - near, 0.0) / (z_r * near) * per_angle, vec2<f32>(params.max_radius));
        let size = f32(frame.map_size);
        var blocker_sum = 0.0;
        var blockers = 0u;
        let nb = params.blocker_taps;
        for (var j = 0u; j < nb; j = j + 1u) {
            for (var i = 0u; i < nb; i = i + 1u) {
                let o = vec2<f32>(midpoint(i, nb, search.x), midpoint(j, nb, search.y));
                let texel = floor(px.uv + o);
                if (texel.x < 0.0 || texel.y < 0.0 || texel.x >= size || texel.y >= size) {
                    continue;
                }
                let stored = map_depth(frame, shadow_maps, s, vec2<i32>(texel));
                if (!depth_passes(s, z_r - length(o) * slope, stored)) {
                    blocker_sum = blocker_sum + s.depth_lin_a / (stored + s.depth_lin_b);
                    blockers = blockers + 1u;
                }
            }
        }
        if (f > 0.0) {
            atomicMin(&regions[base + 2u], ordered(f / z_r));
        }
        if (blockers > 0u) {
            // pcss's filter of the penumbra's half-width: a penumbra pixel where it is neither
            // all lit nor all blocked (the search alone also counts blockers too near the
            // receiver to block it, and cannot tell the umbra).
            let z_b = blocker_sum / f32(blockers);
            let r = min(light * (z_r - z_b) / (z_r * z_b) * per_angle, vec2<f32>(params.max_radius));
            var lit = 0.0;
            for (var j = 0u; j < nb; j = j + 1u) {
                for (var i = 0u; i < nb; i = i + 1u) {
                    let o = vec2<f32>(midpoint(i, nb, r.x), midpoint(j, nb, r.y));
                    lit = lit + tap_lit(frame, s, shadow_maps, z_r - length(o) * slope, px.uv + o);
                }
            }
            if (lit > 0.0 && lit < f32(nb * nb)) {
                // Its full width at the receiver, by similar triangles.
                atomicAdd(&regions[base + 1u], 1u);
                let width = max(params.light_u, params.light_v) * max(z_r - z_b, 0.0) / z_b;
                atomicMin(&regions[base + 3u], ordered(width / z_r));
            }
        }
    }
    let p = px.position;
    atomicMin(&regions[base + 4u], ordered(p.x));
    atomicMin(&regions[base + 5u], ordered(p.y));
    atomicMin(&regions[base + 6u], ordered(p.z));
    atomicMax(&regions[base + 7u], ordered(p.x));
    atomicMax(&regions[base + 8u], ordered(p.y));
    atomicMax(&regions[base + 9u], ordered(p.z));
}

// A region's weight P^0.4 A^0.6 (docs/regions.md, "Samples").
fn weight(area: u32, penumbra: u32) -> f32 {
    return pow(f32(penumbra), 0.4) * pow(f32(area), 0.6);
}

@compute @workgroup_size(64, 1, 1)
fn total(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.region_count) {
        return;
    }
    let base = gid.x * REGION_WORDS;
    let area = atomicLoad(&regions[base]);
    let penumbra = atomicLoad(&regions[base + 1u]);
    if (penumbra > 0u) {
        atomicAdd(&totals[0], u32(round(WEIGHT_SCALE * weight(area, penumbra))));
    }
    atomicAdd(&totals[1], area);
}

// Samples per side of a region with `area` geometry and `penumbra` penumbra pixels: the least
// cost Σ A n² under Σ P (1/12) n^-3 ≤ T² N gives n = k (P/A)^0.2, with k³ = Σ P^0.4 A^0.6 / (12 T² N).
fn samples_of(area: u32, penumbra: u32) -> u32 {
    if (penumbra == 0u) {
        return 1u;
    }
    let sum = f32(atomicLoad(&totals[0])) / WEIGHT_SCALE;
    let n_geo = f32(max(atomicLoad(&totals[1]), 1u));
    let k = pow(sum / (12.0 * params.rmse_target * params.rmse_target * n_geo), 1.0 / (2.0 * SAMPLING_ORDER));
    let n = k * pow(f32(penumbra) / f32(area), 0.2);
    return clamp(u32(ceil(min(n, f32(params.max_n)))), 1u, params.max_n);
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
    let n = samples_of(atomicLoad(&regions[base]), atomicLoad(&regions[base + 1u]));
    let c = class_of(n);
    let section = c * params.section_words;
    let slot = atomicAdd(&class_tiles[section], 1u);
    atomicStore(&class_tiles[section + TILE_LIST_HEADER + slot], tile);
    // A texel may be as wide as the finest pixel footprint, or as one step of the grid across the
    // narrowest penumbra (its width over n): tangent units, as the light sees them.
    let foot = atomicLoad(&regions[base + 2u]);
    let width = atomicLoad(&regions[base + 3u]);
    var texel = foot;
    if (width != 0xffffffffu) {
        texel = max(foot, ordered(unordered(width) / f32(n)));
    }
    let cb = c * CLASS_WORDS;
    atomicAdd(&classes[cb], 1u);
    atomicMin(&classes[cb + 1u], texel);
    for (var k = 0u; k < 3u; k = k + 1u) {
        atomicMin(&classes[cb + 2u + k], atomicLoad(&regions[base + 4u + k]));
        atomicMax(&classes[cb + 5u + k], atomicLoad(&regions[base + 7u + k]));
    }
}
