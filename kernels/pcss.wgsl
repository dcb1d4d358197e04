// pcss: percentage-closer soft shadows (Fernando 2005). A blocker search over the region of the
// centre map through which p sees the light, then the penumbra half-width from similar triangles,
//   w = (d_receiver - d_blocker) * w_light / d_blocker   (world, at the receiver),
// as texels of the map, then a box PCF of that half-width. Depths are linear (distance along the
// light's normal); taps sit at cell midpoints of an N x N grid.

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> settings: GpuFilter;
@group(0) @binding(2) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(3) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(5) var shadow_maps: ShadowMaps;
@group(0) @binding(6) var<storage, read_write> visibility: array<f32>;

fn midpoint(i: u32, n: u32, r: f32) -> f32 {
    return -r + 2.0 * r * (f32(i) + 0.5) / f32(n);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) band_gid: vec3<u32>) {
    // One dispatch per band of rows (docs/gpu-frame.md §8): the pixel is the band's, V is bound from
    // the band's first pixel.
    let gid = vec3<u32>(band_gid.x, band_gid.y + frame.band_first_row, band_gid.z);
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    // One map, or the face of a point light's cube that holds the pixel's direction.
    let s = samples[face_offset(frame, samples[0], textureLoad(gbuffer_position, vec2<i32>(gid.xy), 0).xyz)];
    let px = map_pixel(frame, s, gbuffer_position, gbuffer_normal, vec2<i32>(gid.xy));
    if (!px.geometry) {
        return;
    }
    let index = gid.y * frame.width + gid.x - band_base(frame);
    if (px.lookup.kind != LOOKUP_COMPARE) {
        visibility[index] = select(0.0, 1.0, px.lookup.kind == LOOKUP_OUTSIDE);
        return;
    }
    let position = px.position;
    let normal = px.normal;
    let lookup = px.lookup;
    let t = px.uv;
    let z_r = lookup.depth_limit;
    let slope = slope_per_texel(frame, s, position.xyz, normal);
    let ortho = s.orthographic != 0u;
    let near = select(s.depth_lin_a / s.depth_lin_b, s.depth_lin_b, ortho);
    // Texels per unit of angular offset; a blocker at depth z shifts by o (z_r - z) / (z_r z).
    // Orthographic: light is tan of the sun's angular radius and a texel a world size, so the
    // shift is o (z_r - z): the division by z_r z becomes one.
    let per_angle = 1.0 / s.texel_angle;
    let light = vec2<f32>(settings.light_u, settings.light_v) * 0.5;
    let search = min(light * max(z_r - near, 0.0) / select(z_r * near, 1.0, ortho) * per_angle, vec2<f32>(settings.max_radius));
    let size = f32(frame.map_size);
    var blocker_sum = 0.0;
    var blockers = 0u;
    let nb = settings.blocker_taps;
    for (var j = 0u; j < nb; j = j + 1u) {
        for (var i = 0u; i < nb; i = i + 1u) {
            let o = vec2<f32>(midpoint(i, nb, search.x), midpoint(j, nb, search.y));
            let texel = floor(t + o);
            if (texel.x < 0.0 || texel.y < 0.0 || texel.x >= size || texel.y >= size) {
                continue;
            }
            let stored = map_depth(frame, shadow_maps, s, vec2<i32>(texel));
            if (!depth_passes(s, z_r - length(o) * slope, stored)) {
                blocker_sum = blocker_sum + select(s.depth_lin_a / (stored + s.depth_lin_b), s.depth_lin_a * stored + s.depth_lin_b, ortho);
                blockers = blockers + 1u;
            }
        }
    }
    if (blockers == 0u) {
        visibility[index] = 1.0;
        return;
    }
    let z_b = blocker_sum / f32(blockers);
    let r = min(light * (z_r - z_b) / select(z_r * z_b, 1.0, ortho) * per_angle, vec2<f32>(settings.max_radius));
    let n = settings.taps;
    var lit = 0.0;
    for (var j = 0u; j < n; j = j + 1u) {
        for (var i = 0u; i < n; i = i + 1u) {
            let o = vec2<f32>(midpoint(i, n, r.x), midpoint(j, n, r.y));
            lit = lit + tap_lit(frame, s, shadow_maps, z_r - length(o) * slope, t + o);
        }
    }
    visibility[index] = lit / f32(n * n);
}
