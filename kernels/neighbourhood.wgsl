// neighbourhood: the low-quality test of method.md §3. Pixel p is low quality for quad q when
// 0 < c_q(p) < 4 and all 8 neighbours (clamped at the screen edge) have the same c_q; a background
// or unevaluated neighbour (byte 0) counts as different. One bit per pixel, 32 per flag word.
//  main: every flag word, looping over the batch's quads; list: one item each (scope = local),
//  which also counts the quads' low-quality pixels (quad_count's job under scope = global).

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> level: GpuLevel;
@group(0) @binding(2) var<storage, read> counts: array<u32>;
@group(0) @binding(3) var<storage, read_write> flags: array<u32>;
@group(0) @binding(4) var<storage, read> items: array<vec2<u32>>;
@group(0) @binding(5) var<storage, read_write> flags_atomic: array<atomic<u32>>;
@group(0) @binding(6) var<storage, read> item_total: array<u32>;
// Per comparison-map word: its bytes when uniform, else MIXED_WORD (reproject_count main; all
// MIXED_WORD under scope = local, whose comparison maps are dense).
@group(0) @binding(7) var<storage, read> word_state: array<u32>;
// list: each low-quality item also adds 1 to its quad's counter, so scope = local needs no
// quad_count pass over every flag word of every quad (low-quality items are few).
@group(0) @binding(8) var<storage, read_write> quad_counters: array<atomic<u32>>;

fn byte_at(q: u32, x: i32, y: i32) -> u32 {
    let cx = u32(clamp(x, 0, i32(frame.width) - 1));
    let cy = u32(clamp(y, 0, i32(frame.height) - 1));
    let at = cy * level.words_per_row + cx / 4u;
    let state = word_state[at];
    if (state != MIXED_WORD) {
        return count_byte(state, cx);
    }
    let words = frame.height * level.words_per_row;
    return count_byte(counts[q * words + at], cx);
}

fn low_quality(q: u32, x: i32, y: i32) -> bool {
    let b = byte_at(q, x, y);
    // bytes 2..4 are c = 1..3: partly lit by the quad's corners
    if (b < 2u || b > 4u) {
        return false;
    }
    for (var dy = -1; dy <= 1; dy = dy + 1) {
        for (var dx = -1; dx <= 1; dx = dx + 1) {
            if (byte_at(q, x + dx, y + dy) != b) {
                return false;
            }
        }
    }
    return true;
}

// One thread per flag word (32 pixels) tests every quad of the batch (the quads loop inside the
// thread), so the word states are read once: a flag word without a mixed comparison-map word has no
// low-quality pixel for any quad and costs one zero store per quad.
@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let words = frame.height * level.flag_words_per_row;
    if (gid.x >= words) {
        return;
    }
    let y = gid.x / level.flag_words_per_row;
    let x0 = (gid.x % level.flag_words_per_row) * 32u;
    let count_words = frame.height * level.words_per_row;
    let row = y * level.words_per_row;
    var mixed = 0u;
    for (var w = 0u; w < 8u; w = w + 1u) {
        let wx = x0 / 4u + w;
        if (wx < level.words_per_row && word_state[row + wx] == MIXED_WORD) {
            mixed = mixed | (1u << w);
        }
    }
    for (var qi = 0u; qi < level.quad_count; qi = qi + 1u) {
        var bits = 0u;
        for (var w = 0u; w < 8u; w = w + 1u) {
            let wx = x0 / 4u + w;
            // Most mixed words hold no partly lit pixel for this quad: reject them four pixels at a time.
            if ((mixed & (1u << w)) == 0u || !has_partial_byte(counts[qi * count_words + row + wx])) {
                continue;
            }
            for (var b = 0u; b < 4u; b = b + 1u) {
                let x = wx * 4u + b;
                if (x < frame.width && low_quality(qi, i32(x), i32(y))) {
                    bits = bits | (1u << (w * 4u + b));
                }
            }
        }
        flags[qi * words + gid.x] = bits;
    }
}

@compute @workgroup_size(64, 1, 1)
fn list(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (list_index(gid) >= item_total[0]) {
        return;
    }
    let item = items[list_index(gid)];
    let x = item.x % frame.width;
    let y = item.x / frame.width;
    if (low_quality(item.y, i32(x), i32(y))) {
        let words = frame.height * level.flag_words_per_row;
        atomicOr(&flags_atomic[item.y * words + y * level.flag_words_per_row + x / 32u], 1u << (x % 32u));
        atomicAdd(&quad_counters[item.y], 1u);
    }
}
