// compact (scope = local): each evaluated (pixel, quad) item either goes on to the quad's four
// children (the quad split and p lay in its penumbra, 0 < c < 4, or beside a pixel that does), or becomes a probe (the quad
// split but p's corners agree: probe.wgsl tests the new samples next level), or adds the quad's
// uniform share area(q)/area(light) * c/4 to p, kept exactly as the integer c * 4^(max_level - level).
//  seed: the level-0 items, one per geometry pixel (it counts them too); main: one item each; resolve: integer -> V.
// (reproject_count `begin` makes the appended items a level's work.)
// With scissor or cull on (main_rects), every child corner's shadow-map texel rectangle grows to
// cover p, and the culling tile p looks up in keeps the largest depth limit tested in it.

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> level: GpuLevel;
@group(0) @binding(2) var<storage, read> items: array<vec2<u32>>;
@group(0) @binding(3) var<storage, read> counts: array<u32>;
@group(0) @binding(4) var<storage, read> split_base: array<u32>;
@group(0) @binding(5) var<storage, read_write> next_items: array<vec2<u32>>;
@group(0) @binding(6) var<storage, read_write> control: GpuControl;
@group(0) @binding(7) var<storage, read_write> visibility_fixed: array<atomic<u32>>;
@group(0) @binding(8) var<storage, read> next_quads: array<GpuQuad>;
@group(0) @binding(9) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(10) var<storage, read_write> rects: array<atomic<u32>>;
@group(0) @binding(11) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(12) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(13) var<storage, read_write> visibility: array<f32>;
@group(0) @binding(14) var<storage, read> item_total: array<u32>;
@group(0) @binding(16) var<storage, read_write> probes: array<vec2<u32>>;
@group(0) @binding(17) var<storage, read_write> tiles: array<atomic<u32>>;

fn grow_rect(k: u32, position: vec3<f32>, normal: vec3<f32>) {
    let lookup = shadow_lookup(frame, samples[k], position, normal);
    if (lookup.kind == LOOKUP_COMPARE) {
        // Most items land inside what earlier items already grew: a plain load first, so only the
        // few that grow a bound pay for an atomic (the bounds only grow, so the result is the same).
        let t = vec2<u32>(lookup.texel);
        let r = k * 4u;
        if (t.x < atomicLoad(&rects[r])) { atomicMin(&rects[r], t.x); }
        if (t.y < atomicLoad(&rects[r + 1u])) { atomicMin(&rects[r + 1u], t.y); }
        if (t.x > atomicLoad(&rects[r + 2u])) { atomicMax(&rects[r + 2u], t.x); }
        if (t.y > atomicLoad(&rects[r + 3u])) { atomicMax(&rects[r + 3u], t.y); }
        // Positive floats order as their bits. A limit <= 0 is lit whatever the map holds.
        let limit = bitcast<u32>(lookup.depth_limit);
        let tile = k * CULL_TILE_WORDS + cull_tile(lookup.texel, frame.map_size);
        if (lookup.depth_limit > 0.0 && limit > atomicLoad(&tiles[tile])) {
            atomicMax(&tiles[tile], limit);
        }
    }
}

var<workgroup> group_items: atomic<u32>;
var<workgroup> group_base: u32;
var<workgroup> group_probes: atomic<u32>;
var<workgroup> group_probe_base: u32;

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    compact_item(list_index(gid), lid, false);
}

// With scissor or cull on. A separate entry point because the rectangle code, even never run,
// made main more than twice as slow on a CPU device (lavapipe); `grow` is a constant in each.
@compute @workgroup_size(64, 1, 1)
fn main_rects(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    compact_item(list_index(gid), lid, true);
}

// Appends are gathered per workgroup first: one global atomic per workgroup instead of one per item
// (a single append counter hit by every item serialises on CPU devices and stalls GPUs).
fn compact_item(index: u32, lid: u32, grow: bool) {
    let valid = index < item_total[0];
    var item = vec2<u32>(0u, 0u);
    var c = 0u;
    var base = NO_SPLIT;
    var local_slot = 0u;
    var refine = false;
    var probe = false;
    var probe_slot = 0u;
    if (valid) {
        item = items[index];
        let x = item.x % frame.width;
        let y = item.x / frame.width;
        let words = frame.height * level.words_per_row;
        c = count_byte(counts[item.y * words + y * level.words_per_row + x / 4u], x) - 1u;
        base = split_base[item.y];
        refine = base != NO_SPLIT && c > 0u && c < 4u;
        // The halo: a uniform pixel beside a pixel in this quad's penumbra refines too. Penumbrae
        // narrower than the lattice's spacing otherwise hide between its samples at silhouettes
        // and contacts (docs/method.md §4.4).
        if (base != NO_SPLIT && !refine) {
            for (var dy = -1; dy <= 1; dy = dy + 1) {
                for (var dx = -1; dx <= 1; dx = dx + 1) {
                    let nx = i32(x) + dx;
                    let ny = i32(y) + dy;
                    if (nx >= 0 && ny >= 0 && nx < i32(frame.width) && ny < i32(frame.height)) {
                        let nb = count_byte(counts[item.y * words + u32(ny) * level.words_per_row + u32(nx) / 4u], u32(nx));
                        if (nb >= 2u && nb <= 4u) {
                            refine = true;
                        }
                    }
                }
            }
        }
        probe = base != NO_SPLIT && !refine;
        if (refine) {
            local_slot = atomicAdd(&group_items, 4u);
        }
        if (probe) {
            probe_slot = atomicAdd(&group_probes, 1u);
        }
    }
    workgroupBarrier();
    if (lid == 0u) {
        group_base = atomicAdd(&control.item_count, atomicLoad(&group_items));
        group_probe_base = atomicAdd(&control.probe_count, atomicLoad(&group_probes));
    }
    let slot = workgroupUniformLoad(&group_base) + local_slot;
    let probe_at = workgroupUniformLoad(&group_probe_base) + probe_slot;
    if (!valid) {
        return;
    }
    let p = item.x;
    if (refine || probe) {
        if (refine) {
            if (slot + 4u > level.item_capacity) {
                atomicOr(&control.overflow, OVERFLOW_ITEMS);
                return;
            }
            for (var child = 0u; child < 4u; child = child + 1u) {
                next_items[slot + child] = vec2<u32>(p, base + child);
            }
        } else {
            if (probe_at >= level.item_capacity) {
                atomicOr(&control.overflow, OVERFLOW_PROBES);
                return;
            }
            probes[probe_at] = vec2<u32>(p, base | select(0u, PROBE_LIT, c == 4u));
        }
        if (grow) {
            let pixel = vec2<i32>(i32(p % frame.width), i32(p / frame.width));
            let position = textureLoad(gbuffer_position, pixel, 0).xyz;
            let normal = textureLoad(gbuffer_normal, pixel, 0).xyz;
            // Only the split's 5 new points: the next level renders nothing else, and the parent's
            // 4 corners were rendered already (rects and tiles serve maps still to be rendered).
            let q = next_quads[base];
            let h = q.size;
            let row = h * LATTICE_SIDE;
            let k = q.j * LATTICE_SIDE + q.i;
            grow_rect(k + h, position, normal);
            grow_rect(k + row, position, normal);
            grow_rect(k + row + h, position, normal);
            grow_rect(k + row + 2u * h, position, normal);
            grow_rect(k + 2u * row + h, position, normal);
        }
    } else {
        atomicAdd(&visibility_fixed[p], c << (2u * (level.max_level - level.level)));
    }
}

@compute @workgroup_size(8, 8, 1)
fn seed(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let inside = gid.x < frame.width && gid.y < frame.height;
    var geometry = false;
    var local_slot = 0u;
    if (inside) {
        geometry = textureLoad(gbuffer_position, vec2<i32>(gid.xy), 0).w != 0.0;
        if (geometry) {
            local_slot = atomicAdd(&group_items, 1u);
        }
    }
    workgroupBarrier();
    if (lid == 0u) {
        // The level-0 items are the geometry pixels: their count is the share criteria's denominator.
        let n = atomicLoad(&group_items);
        group_base = atomicAdd(&control.item_count, n);
        atomicAdd(&control.geometry_pixels, n);
    }
    let slot = workgroupUniformLoad(&group_base) + local_slot;
    if (!geometry) {
        return;
    }
    if (slot >= level.item_capacity) {
        atomicOr(&control.overflow, OVERFLOW_ITEMS);
        return;
    }
    next_items[slot] = vec2<u32>(gid.y * frame.width + gid.x, 0u);
}

@compute @workgroup_size(8, 8, 1)
fn resolve(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    let p = gid.y * frame.width + gid.x;
    visibility[p] = f32(atomicLoad(&visibility_fixed[p])) / f32(4u << (2u * level.max_level));
}
