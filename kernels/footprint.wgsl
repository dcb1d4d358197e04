// footprint: the culling tiles of a batch of maps where every geometry pixel tests every map (the
// fixed-sample methods and scope = global, with cull = on). For each (pixel, slot), the
// tile its lookup lands in keeps the largest depth limit tested there, as compact grows them for
// scope = local, so `cull` then drops every triangle that can change no tested texel's outcome.
// Slot z reads samples[z]: the batch's own copy of its sample records, so `cull` reads the same
// slot for both (its slots list is 0..n).

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<storage, read> samples: array<GpuSample>;
@group(0) @binding(2) var gbuffer_position: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(4) var<storage, read_write> tiles: array<atomic<u32>>;
// x: the batch's slots.
@group(0) @binding(5) var<uniform> batch: vec4<u32>;
// `listed`: the tiles whose pixels test the batch's maps (a shade tile list: header, then tiles).
@group(0) @binding(6) var<storage, read> tile_list: array<u32>;

// One invocation per pixel loops over the batch's slots: the G-buffer is read once, and the loop
// bound is uniform (a dispatch over (pixel, slot) was four times slower on a CPU device).
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    footprint_pixel(gid.xy);
}

// The same over the pixels of a tile list alone, one workgroup per listed tile (dispatched
// indirectly from the list's header): where a map is tested by some tiles only (a `regions`
// group's), only their pixels raise its culling tiles, so `cull` keeps only their triangles.
@compute @workgroup_size(8, 8, 1)
fn listed(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    footprint_pixel(tile_pixel(tile_list[TILE_LIST_HEADER + group.x], lid, frame.width).xy);
}

fn footprint_pixel(p: vec2<u32>) {
    if (p.x >= frame.width || p.y >= frame.height) {
        return;
    }
    let pixel = vec2<i32>(p);
    let position = textureLoad(gbuffer_position, pixel, 0);
    if (position.w == 0.0) {
        return;
    }
    let n = textureLoad(gbuffer_normal, pixel, 0).xyz;
    for (var z = 0u; z < batch.x; z = z + 1u) {
        let lookup = shadow_lookup(frame, samples[z], position.xyz, n);
        // Positive floats order as their bits. A limit <= 0 is lit whatever the map holds.
        if (lookup.kind == LOOKUP_COMPARE && lookup.depth_limit > 0.0) {
            let tile = z * CULL_TILE_WORDS + cull_tile(lookup.texel, frame.map_size);
            let limit = bitcast<u32>(lookup.depth_limit);
            // Neighbouring pixels mostly share a tile and a limit: a plain load first, so only a
            // pixel that raises the tile pays for an atomic.
            if (limit > atomicLoad(&tiles[tile])) {
                atomicMax(&tiles[tile], limit);
            }
        }
    }
}
