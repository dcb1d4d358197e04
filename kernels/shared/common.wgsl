// Shared prelude, concatenated before every kernel: WGSL twins of the Rust `Gpu*` structs
// (src/gpu/structs.rs; a test compares their layouts) and the one shadow-map test every method uses.
// Depths are read through `map_depth` (kernels/shared/maps_plain.wgsl or maps_hybrid.wgsl, one of
// which is concatenated after this prelude), so every method works on either representation.

struct GpuFrame {
    width: u32,
    height: u32,
    map_size: u32,
    flags: u32,
    light_center: vec4<f32>,
    light_normal: vec4<f32>,
    bias_constant: f32,
    bias_slope: f32,
    normal_offset: f32,
    max_slope: f32,
    // Bands of rows (docs/gpu-frame.md §8): a per-pixel buffer too large for one binding is bound
    // a band at a time. A band's dispatch gets a copy of the frame whose band_first_row is its
    // first row; band_rows is every band's height (0: one band, the whole image), and the geometry
    // tile list holds one section of tile_section_words words per band.
    band_first_row: u32,
    band_rows: u32,
    tile_section_words: u32,
    bands: u32,
}

// The pixel index where the dispatch's band starts: buffers bound by band are indexed from it.
fn band_base(frame: GpuFrame) -> u32 {
    return frame.band_first_row * frame.width;
}

// Rows of the dispatch's band.
fn band_height(frame: GpuFrame) -> u32 {
    let rest = frame.height - min(frame.band_first_row, frame.height);
    return select(rest, min(frame.band_rows, rest), frame.band_rows != 0u);
}

struct GpuSample {
    light_from_world: mat4x4<f32>,
    // The light point (w = 1); for an orthographic map the unit direction towards the light (w = 0).
    position: vec4<f32>,
    // Texel footprint per unit of linear depth: world size of a texel at depth z is z * texel_angle.
    // An orthographic map's clip.w is 1, so there it is the texel's world size, the same at every depth.
    texel_angle: f32,
    // Linear depth of a stored depth d is depth_lin_a / (d + depth_lin_b) (both negative);
    // orthographic: depth_lin_a * d + depth_lin_b (the depth range and the near plane).
    depth_lin_a: f32,
    depth_lin_b: f32,
    layer: u32,
    array: u32,
    lattice: u32,
    orthographic: u32,
    // 0, or 1 + the cube face (0..5: +x, -x, +y, -y, +z, -z) of a point light's map (cube_face).
    cube_face: u32,
}

// The way from p to the sample's light: to the light point, or the orthographic map's direction.
fn toward_light(s: GpuSample, p: vec3<f32>) -> vec3<f32> {
    return s.position.xyz - p * s.position.w;
}

// True when linear depth `limit` is at or in front of the stored depth d (lit): limit <= linear(d),
// compared without a division for a perspective map (d + depth_lin_b < 0).
fn depth_passes(s: GpuSample, limit: f32, stored: f32) -> bool {
    let perspective = limit * (stored + s.depth_lin_b) >= s.depth_lin_a;
    let orthographic = limit <= s.depth_lin_a * stored + s.depth_lin_b;
    return select(perspective, orthographic, s.orthographic != 0u);
}

// The cube face (0..5: +x, -x, +y, -y, +z, -z) whose axis dominates d; ties go to the earlier axis,
// so every direction has exactly one face.
fn cube_face(d: vec3<f32>) -> u32 {
    let a = abs(d);
    let x = a.x >= a.y && a.x >= a.z;
    let y = !x && a.y >= a.z;
    let axis = select(select(2u, 1u, y), 0u, x);
    let along = select(select(d.z, d.y, y), d.x, x);
    return axis * 2u + select(0u, 1u, along < 0.0);
}

// A point light's sample is six consecutive cube faces, face 0 first: the one of them that holds
// p's direction from the sphere's centre (frame.light_center), the same for every sample, so the
// faces share the receivers out exactly. Any other sample is its own.
fn face_offset(frame: GpuFrame, s: GpuSample, p: vec3<f32>) -> u32 {
    return select(0u, cube_face(p - frame.light_center.xyz), s.cube_face != 0u);
}

// GpuFrame.flags: the light point must lie above the surface's (geometric) tangent plane, as for a
// ray; without it (self_shadow = "map") the depth test alone decides, as in classic shadow mapping.
const FRAME_FACING_TEST: u32 = 1u;
// GpuFrame.flags: a point light lights every way, so no plane through light_center bounds its lit side.
const FRAME_EVERY_WAY: u32 = 2u;

const LOOKUP_UNLIT: u32 = 0u;    // behind the light's plane, or the sample is below p's tangent plane
const LOOKUP_OUTSIDE: u32 = 1u;  // projects outside the map: nothing there can occlude
const LOOKUP_COMPARE: u32 = 2u;  // compare depth_limit with the map at texel

struct ShadowLookup {
    texel: vec2<i32>,
    kind: u32,
    depth_limit: f32,
}

// Where surface point p (normal n, facing the camera) lands in sample s's map, with the bias applied.
// Bias is in texels at p's depth, so it does not depend on scene scale: constant + slope * tan(angle).
// Straight-line code, the cases chosen by select: a CPU device runs both sides of a branch anyway,
// and inside one (a mask) it reads every uniform lane by lane (docs/gpu-frame.md §4).
fn shadow_lookup(frame: GpuFrame, s: GpuSample, p: vec3<f32>, n: vec3<f32>) -> ShadowLookup {
    let to_light = toward_light(s, p);
    let light_side = dot(p - frame.light_center.xyz, frame.light_normal.xyz);
    let facing = dot(n, to_light);
    // A cube face other than the one holding p's direction: p is counted by that face instead.
    let other_face = s.cube_face != 0u && cube_face(p - frame.light_center.xyz) + 1u != s.cube_face;
    let unlit = (light_side <= 0.0 && (frame.flags & FRAME_EVERY_WAY) == 0u) || (facing <= 0.0 && (frame.flags & FRAME_FACING_TEST) != 0u) || other_face;
    let depth = dot(vec4<f32>(s.light_from_world[0].w, s.light_from_world[1].w, s.light_from_world[2].w, s.light_from_world[3].w), vec4<f32>(p, 1.0));
    let texel_world = depth * s.texel_angle;
    let q = p + n * (frame.normal_offset * texel_world);
    let clip = s.light_from_world * vec4<f32>(q, 1.0);
    let size = f32(frame.map_size);
    let uv = vec2<f32>(clip.x / clip.w * 0.5 + 0.5, 0.5 - clip.y / clip.w * 0.5);
    // A cube face never leaves its receiver outside: where rounding or the normal offset carries p
    // just across the face's edge, the edge texel answers.
    let cube = s.cube_face != 0u;
    let t = select(floor(uv * size), clamp(floor(uv * size), vec2<f32>(0.0), vec2<f32>(size - 1.0)), cube);
    let outside = clip.w <= 0.0 || t.x < 0.0 || t.y < 0.0 || t.x >= size || t.y >= size;
    let cos_angle = abs(facing) / length(to_light);
    let tan_angle = min(sqrt(max(1.0 - cos_angle * cos_angle, 0.0)) / max(cos_angle, 1e-6), frame.max_slope);
    var out: ShadowLookup;
    out.kind = select(select(LOOKUP_COMPARE, LOOKUP_OUTSIDE, outside), LOOKUP_UNLIT, unlit);
    let compare = out.kind == LOOKUP_COMPARE;
    // Texel (0, 0) and limit 0 unless compared, as the twin returns them.
    out.texel = select(vec2<i32>(0, 0), vec2<i32>(t), compare);
    // Linear depth: clip.w for a perspective map, the depth range's share for an orthographic one.
    let linear = select(clip.w, s.depth_lin_a * clip.z + s.depth_lin_b, s.orthographic != 0u);
    out.depth_limit = select(0.0, linear - texel_world * (frame.bias_constant + frame.bias_slope * tan_angle), compare);
    return out;
}

// 1 when p is lit by the sample whose map holds `stored` at the looked-up texel.
// Compared in linear depth without a division: limit <= a / (d + b) with d + b < 0.
fn shadow_compare(s: GpuSample, lookup: ShadowLookup, stored: f32) -> u32 {
    let lit = select(0u, 1u, depth_passes(s, lookup.depth_limit, stored));
    return select(select(0u, 1u, lookup.kind == LOOKUP_OUTSIDE), lit, lookup.kind == LOOKUP_COMPARE);
}

// ---- geometry tiles ----
// Per-pixel kernels that run without branches (shade's and shadow_test's blocks) run one 8x8
// workgroup per tile that holds a geometry pixel: a CPU device computes every lane of a workgroup,
// so a tile of background only would cost as much as any other (about half the image on default).
// The list is made once per frame with the G-buffer (shade.wgsl `geometry_tiles`). Words 0..2 are
// the indirect dispatch (tile count, 1, 1), word 3 is padding, the tile indices follow.
const TILE_LIST_HEADER: u32 = 4u;

// Pixel of lane lid in tile `tile` (row-major over the image's 8x8 tiles).
fn tile_pixel(tile: u32, lid: vec3<u32>, width: u32) -> vec3<u32> {
    let tiles_x = (width + 7u) / 8u;
    return vec3<u32>((tile % tiles_x) * 8u + lid.x, (tile / tiles_x) * 8u + lid.y, 0u);
}

// ---- adaptive light-source sampling (method.md §3-4) ----

// The 17x17 lattice of light points (L_max = 4); lattice index k = j * 17 + i.
const LATTICE_SIDE: u32 = 17u;
const LATTICE_POINTS: u32 = 289u;
// Per-pixel bit masks over the lattice: bit k of word k / 32.
const MASK_WORDS: u32 = 10u;
const NO_SPLIT: u32 = 0xffffffffu;

// Culling tiles (scope = local): each lattice sample's map is cut into CULL_TILES x CULL_TILES
// tiles, one word each: 0 where no pixel that tests the sample looks up a texel, else the largest
// depth limit (f32 bits, > 0) those pixels compare the map with.
const CULL_TILES: u32 = 256u;
const CULL_TILE_WORDS: u32 = 65536u;

fn cull_tile(texel: vec2<i32>, map_size: u32) -> u32 {
    let t = vec2<u32>(texel) * CULL_TILES / map_size;
    return t.y * CULL_TILES + t.x;
}
// Word 9 of a mask holds lattice index 288 in bit 0; its top bits summarise the pixel over every map
// tested so far, so counting can skip pixels that all maps agree on (c is 0 or 4 for every quad).
const SUMMARY_WORD: u32 = 9u;
const SUMMARY_GEOMETRY: u32 = 0x80000000u;
const SUMMARY_ANY_LIT: u32 = 0x40000000u;
const SUMMARY_ANY_UNLIT: u32 = 0x20000000u;

struct GpuLevel {
    level: u32,
    max_level: u32,
    quad_count: u32,
    first_quad: u32,
    split_threshold: u32,
    split_mode: u32,
    words_per_row: u32,
    flag_words_per_row: u32,
    item_capacity: u32,
    work_count: u32,
    dense_groups_x: u32,
    quad_capacity: u32,
    pad0: u32,
    split_share: f32,
    // shadow_test: 1 takes the test list's length from the append counter (control word 1).
    requested: u32,
    // subdivide: the hysteresis margin (low-quality pixels) of a quad the previous frame did not split.
    hold: u32,
}

// GpuLevel.split_mode (Rust: gpu::structs::SPLIT_*): split when the count exceeds
// split_threshold, always, never, or when it exceeds split_share x the geometry pixels.
const SPLIT_THRESHOLD: u32 = 0u;
const SPLIT_ALWAYS: u32 = 1u;
const SPLIT_NEVER: u32 = 2u;
const SPLIT_SHARE: u32 = 3u;

struct GpuQuad {
    i: u32,
    j: u32,
    size: u32,
    parent: u32,
}

struct GpuControl {
    next_quad_count: atomic<u32>,
    new_sample_count: atomic<u32>,
    overflow: atomic<u32>,
    item_count: atomic<u32>,
    geometry_pixels: atomic<u32>,
    probe_count: atomic<u32>,
    // scope = local: shadow-map lookups this level (shadow_test `list` and `probes`).
    lookups: atomic<u32>,
    pad1: u32,
}

// GpuControl.overflow's bits (Rust: gpu::structs::OVERFLOW_*, decoded by LevelReport::overflow_error).
const OVERFLOW_QUADS: u32 = 1u;
const OVERFLOW_ITEMS: u32 = 2u;
const OVERFLOW_PROBES: u32 = 4u;

// scope = local's item and probe passes dispatch indirectly, 64 items per workgroup. One dimension
// holds at most 65535 workgroups (WebGPU's guaranteed limit; a larger indirect dispatch is dropped
// whole), 4,194,240 items: a longer list spreads its workgroups over rows of LIST_GROUPS_X.
// (Rust twin: stages::adaptive_buffers::list_dispatch.)
const LIST_GROUPS_X: u32 = 65535u;

// The dispatch size of a list of n items.
fn list_dispatch(n: u32) -> vec3<u32> {
    let groups = (n + 63u) / 64u;
    return vec3<u32>(min(groups, LIST_GROUPS_X), max(1u, (groups + LIST_GROUPS_X - 1u) / LIST_GROUPS_X), 1u);
}

// The list index of an invocation of such a dispatch (every row but the last is LIST_GROUPS_X wide).
fn list_index(gid: vec3<u32>) -> u32 {
    return gid.y * (LIST_GROUPS_X * 64u) + gid.x;
}

// Lattice index of corner c (0..3: (0,0), (1,0), (0,1), (1,1)) of quad q.
fn quad_corner(q: GpuQuad, c: u32) -> u32 {
    let i = q.i + (c & 1u) * q.size;
    let j = q.j + (c >> 1u) * q.size;
    return j * LATTICE_SIDE + i;
}

// A probe's second word: its parent's first child in this level's quads, | PROBE_LIT when the
// parent's corners were all lit (else all unlit).
const PROBE_LIT: u32 = 0x80000000u;

// Lattice index of new point n (0..4: the edge midpoints and the centre) of the parent quad whose
// first child is q: the children's corners that are not the parent's (probe.wgsl).
fn probe_point(q: GpuQuad, n: u32) -> u32 {
    let h = q.size;
    let points = array<vec2<u32>, 5>(
        vec2<u32>(q.i + h, q.j), vec2<u32>(q.i, q.j + h), vec2<u32>(q.i + h, q.j + h),
        vec2<u32>(q.i + 2u * h, q.j + h), vec2<u32>(q.i + h, q.j + 2u * h));
    return points[n].y * LATTICE_SIDE + points[n].x;
}

// Comparison-map bytes hold c + 1 (1..5); 0 means background or not evaluated for this quad.
// word_state of a comparison-map word (scope = global): the word's 4 bytes, the same for every quad,
// when no pixel in it is mixed (all its maps agree); MIXED_WORD when the quads' words differ and
// only the comparison maps hold them. Bytes are at most 5, so MIXED_WORD is never a uniform word.
const MIXED_WORD: u32 = 0xffffffffu;

fn count_byte(word: u32, x: u32) -> u32 {
    return (word >> ((x & 3u) * 8u)) & 0xffu;
}

// Whether any of a word's four bytes is 2..4 (c = 1..3, partly lit). Bytes are at most 5, so adding
// 126 sets a byte's top bit exactly when it is >= 2, and adding 123 exactly when it is >= 5.
fn has_partial_byte(word: u32) -> bool {
    let at_least_2 = (word + 0x7e7e7e7eu) & 0x80808080u;
    let at_least_5 = (word + 0x7b7b7b7bu) & 0x80808080u;
    return (at_least_2 & ~at_least_5) != 0u;
}

// ---- single-map filtering (pcf, pcss, moments, blur, reconstruct) ----

struct GpuFilter {
    kind: u32,
    taps: u32,
    blocker_taps: u32,
    order: u32,
    radius: f32,
    darkening: f32,
    light_u: f32,
    light_v: f32,
    c_pos: f32,
    c_neg: f32,
    bleed: f32,
    moment_bias: f32,
    layers: u32,
    blur_radius: u32,
    max_radius: f32,
    depth_offset: f32,
}

// Continuous texel coordinate of p in sample s's map: the point `shadow_lookup` floors to a texel.
fn shadow_lookup_uv(frame: GpuFrame, s: GpuSample, p: vec3<f32>, n: vec3<f32>) -> vec2<f32> {
    let depth = dot(vec4<f32>(s.light_from_world[0].w, s.light_from_world[1].w, s.light_from_world[2].w, s.light_from_world[3].w), vec4<f32>(p, 1.0));
    let texel_world = depth * s.texel_angle;
    let q = p + n * (frame.normal_offset * texel_world);
    let clip = s.light_from_world * vec4<f32>(q, 1.0);
    let uv = vec2<f32>(clip.x / clip.w * 0.5 + 0.5, 0.5 - clip.y / clip.w * 0.5);
    return uv * f32(frame.map_size);
}

// One pixel of a single-map filter (pcf, pcss, reconstruct): the G-buffer point, where it lands in
// the map and at which texel coordinate. Kernels write V directly unless lookup.kind is COMPARE.
struct MapPixel {
    geometry: bool,
    position: vec3<f32>,
    normal: vec3<f32>,
    lookup: ShadowLookup,
    uv: vec2<f32>,
}

fn map_pixel(frame: GpuFrame, s: GpuSample, gbuffer_position: texture_2d<f32>, gbuffer_normal: texture_2d<f32>, pixel: vec2<i32>) -> MapPixel {
    var out: MapPixel;
    let position = textureLoad(gbuffer_position, pixel, 0);
    out.geometry = position.w != 0.0;
    if (!out.geometry) {
        return out;
    }
    out.position = position.xyz;
    out.normal = textureLoad(gbuffer_normal, pixel, 0).xyz;
    out.lookup = shadow_lookup(frame, s, out.position, out.normal);
    if (out.lookup.kind == LOOKUP_COMPARE) {
        out.uv = shadow_lookup_uv(frame, s, out.position, out.normal);
    }
    return out;
}

// World depth change per texel of offset along p's tangent plane (texel size · tan of the light
// angle, clamped like the slope bias): a tap r texels away compares against limit - r · this, so
// filtering a sloped receiver does not shadow the receiver itself.
fn slope_per_texel(frame: GpuFrame, s: GpuSample, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let to_light = toward_light(s, p);
    let depth = dot(vec4<f32>(s.light_from_world[0].w, s.light_from_world[1].w, s.light_from_world[2].w, s.light_from_world[3].w), vec4<f32>(p, 1.0));
    let cos_angle = abs(dot(n, to_light)) / length(to_light);
    let tan_angle = min(sqrt(max(1.0 - cos_angle * cos_angle, 0.0)) / max(cos_angle, 1e-6), frame.max_slope);
    return depth * s.texel_angle * tan_angle;
}

// One depth-map tap at continuous texel coordinate t: 1 when lit (outside the map counts as lit).
// On a cube face a tap across the face's edge reads the edge texel (clamped), not the next face.
fn tap_lit(frame: GpuFrame, s: GpuSample, maps: ShadowMaps, limit: f32, t: vec2<f32>) -> f32 {
    let size = f32(frame.map_size);
    let texel = select(floor(t), clamp(floor(t), vec2<f32>(0.0), vec2<f32>(size - 1.0)), s.cube_face != 0u);
    if (texel.x < 0.0 || texel.y < 0.0 || texel.x >= size || texel.y >= size) {
        return 1.0;
    }
    let stored = map_depth(frame, maps, s, vec2<i32>(texel));
    return select(0.0, 1.0, depth_passes(s, limit, stored));
}

// Integer hash (PCG) for per-pixel random numbers: exact on CPU and GPU alike.
fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Uniform in [0, 1) from pixel (x, y) and tap i.
fn pixel_random(x: u32, y: u32, i: u32) -> f32 {
    return f32(pcg_hash(x ^ pcg_hash(y ^ pcg_hash(i))) >> 8u) / 16777216.0;
}

// A run of the shadow order (render::shadow_order::runs): (box min, cos of the cone's half angle),
// (box max, its sine), (cone axis, 1 when every face normal lies within the cone).
// Whether every triangle of the run faces away from `eye` (back faces) by a safe margin: each
// normal lies within the cone, every point within the box's bounding sphere.
fn faces_away(eye: vec3<f32>, lo: vec4<f32>, hi: vec4<f32>, axis: vec4<f32>) -> bool {
    if (axis.w != 1.0) {
        return false;
    }
    let centre = (lo.xyz + hi.xyz) * 0.5;
    let radius = length(hi.xyz - lo.xyz) * 0.5;
    let v = centre - eye;
    let along = dot(v, axis.xyz);
    let across = sqrt(max(dot(v, v) - along * along, 0.0));
    return along * lo.w - across * hi.w > radius * 1.01 + length(v) * 1e-3;
}
