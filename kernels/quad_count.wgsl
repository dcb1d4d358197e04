// quad_count: one atomic<u32> of low-quality pixels per quad. Each workgroup sums its flag words in
// workgroup memory first, so the global counter sees one atomic per workgroup, not one per pixel.

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> level: GpuLevel;
@group(0) @binding(2) var<storage, read> flags: array<u32>;
@group(0) @binding(3) var<storage, read_write> quad_counters: array<atomic<u32>>;

var<workgroup> group_sum: atomic<u32>;

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let words = frame.height * level.flag_words_per_row;
    let in_range = gid.x < words && wg.y < level.quad_count;
    if (in_range) {
        let bits = countOneBits(flags[wg.y * words + gid.x]);
        if (bits != 0u) {
            atomicAdd(&group_sum, bits);
        }
    }
    workgroupBarrier();
    if (lid == 0u && wg.y < level.quad_count) {
        let total = atomicLoad(&group_sum);
        if (total != 0u) {
            atomicAdd(&quad_counters[level.first_quad + wg.y], total);
        }
    }
}
