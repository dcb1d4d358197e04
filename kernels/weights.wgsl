// weights (scope = global, corner-to-corner lattice): the sample weights, computed on the GPU from
// the quadtree the levels built, so the frame needs no read-back before shade.
//  leaves: after each level's subdivide, appends the level's unsplit quads to the leaf list;
//  main:   one invocation: the integer numerators of every rendered sample's weight, then
//          w_k = numerator_k / Σ numerators, correctly rounded to f32.
// Numerators: rule level: LEVEL_LCM / (2^level + 1)^2 (the seed); area: each leaf's size^2 to each
// corner (1024ths of the light); coons: size * (after - before) along each edge through every
// rendered sample on it, minus size^2 at each corner (docs/method.md §3). The CPU computes the
// same integers (methods/adaptive/weights.rs), so both give the same f32 weights.

struct GpuWeights {
    rule: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

const RULE_LEVEL: u32 = 0u;
const RULE_AREA: u32 = 1u;
const RULE_COONS: u32 = 2u;
// lcm of (2^l + 1)^2 for l = 0..4: 4, 9, 25, 81, 289.
const LEVEL_LCM: u32 = 2340900u;

@group(0) @binding(0) var<uniform> level: GpuLevel;
@group(0) @binding(1) var<storage, read> quads: array<GpuQuad>;
@group(0) @binding(2) var<storage, read> split_base: array<u32>;
@group(0) @binding(3) var<storage, read_write> leaves: array<GpuQuad>;
// Word 0: leaves appended.
@group(0) @binding(4) var<storage, read_write> leaf_count: array<atomic<u32>>;
@group(0) @binding(5) var<uniform> rule: GpuWeights;
@group(0) @binding(6) var<storage, read> lattice_state: array<u32>;
@group(0) @binding(7) var<storage, read> sample_level: array<u32>;
@group(0) @binding(8) var<storage, read_write> numerators: array<i32>;
@group(0) @binding(9) var<storage, read_write> weights: array<f32>;

@compute @workgroup_size(64, 1, 1)
fn leaves_of_level(@builtin(global_invocation_id) gid: vec3<u32>) {
    let q = gid.x;
    if (q < level.quad_count && split_base[q] == NO_SPLIT) {
        leaves[atomicAdd(&leaf_count[0], 1u)] = quads[q];
    }
}

fn add(i: u32, j: u32, n: i32) {
    let k = j * LATTICE_SIDE + i;
    numerators[k] = numerators[k] + n;
}

// num / den (den > 0), rounded to the nearest f32, ties to even: binary long division.
fn ratio(num: i32, den: i32) -> f32 {
    if (num == 0) {
        return 0.0;
    }
    var r = u32(abs(num));
    var d = u32(den);
    var e = 0i;
    while (r < d) {
        r = r << 1u;
        e = e - 1i;
    }
    while (r >= 2u * d) {
        d = d << 1u;
        e = e + 1i;
    }
    var m = 0u;
    for (var i = 0u; i < 24u; i = i + 1u) {
        let bit = select(0u, 1u, r >= d);
        r = r - bit * d;
        m = (m << 1u) | bit;
        r = r << 1u;
    }
    if (r > d || (r == d && (m & 1u) == 1u)) {
        m = m + 1u;
    }
    let v = ldexp(f32(m), e - 23i);
    return select(v, -v, num < 0);
}

@compute @workgroup_size(1, 1, 1)
fn main() {
    for (var k = 0u; k < LATTICE_POINTS; k = k + 1u) {
        numerators[k] = 0;
        if (rule.rule == RULE_LEVEL && lattice_state[k] != 0u) {
            let d = (1u << sample_level[k]) + 1u;
            numerators[k] = i32(LEVEL_LCM / (d * d));
        }
    }
    if (rule.rule != RULE_LEVEL) {
        let n = atomicLoad(&leaf_count[0]);
        for (var l = 0u; l < n; l = l + 1u) {
            let q = leaves[l];
            let s = q.size;
            if (rule.rule == RULE_COONS) {
                for (var edge = 0u; edge < 4u; edge = edge + 1u) {
                    // (x0, y0) + t (dx, dy), t = 0..=s: bottom, top, left, right.
                    let x0 = q.i + select(0u, s, edge == 3u);
                    let y0 = q.j + select(0u, s, edge == 1u);
                    let dx = select(0u, 1u, edge < 2u);
                    let dy = 1u - dx;
                    var before = 0u;
                    var cur = 0u;
                    for (var t = 1u; t <= s; t = t + 1u) {
                        if (t == s || lattice_state[(y0 + t * dy) * LATTICE_SIDE + x0 + t * dx] != 0u) {
                            add(x0 + cur * dx, y0 + cur * dy, i32(s * (t - before)));
                            before = cur;
                            cur = t;
                        }
                    }
                    add(x0 + cur * dx, y0 + cur * dy, i32(s * (s - before)));
                }
            }
            let corner = select(i32(s * s), -i32(s * s), rule.rule == RULE_COONS);
            add(q.i, q.j, corner);
            add(q.i + s, q.j, corner);
            add(q.i, q.j + s, corner);
            add(q.i + s, q.j + s, corner);
        }
    }
    var total = 0i;
    for (var k = 0u; k < LATTICE_POINTS; k = k + 1u) {
        total = total + numerators[k];
    }
    for (var k = 0u; k < LATTICE_POINTS; k = k + 1u) {
        weights[k] = ratio(numerators[k], total);
    }
}
