// blur: separable box prefilter of the moment planes, radius `blur_radius` texels (set from the
// light size), edges clamped; `horizontal` then `vertical`. Taps are summed in index order, so the
// CPU twin adds in the same order.

@group(0) @binding(0) var<uniform> frame: GpuFrame;
@group(0) @binding(1) var<uniform> settings: GpuFilter;
@group(0) @binding(2) var<storage, read> source: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> destination: array<vec4<f32>>;

fn blur_line(x: u32, y: u32, layer: u32, dx: i32, dy: i32) {
    let size = i32(frame.map_size);
    let r = i32(settings.blur_radius);
    let base = layer * frame.map_size * frame.map_size;
    var sum = vec4<f32>(0.0);
    for (var k = -r; k <= r; k = k + 1) {
        let sx = clamp(i32(x) + k * dx, 0, size - 1);
        let sy = clamp(i32(y) + k * dy, 0, size - 1);
        sum = sum + source[base + u32(sy * size + sx)];
    }
    destination[base + y * frame.map_size + x] = sum / f32(2 * r + 1);
}

@compute @workgroup_size(8, 8, 1)
fn horizontal(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.map_size || gid.y >= frame.map_size || gid.z >= settings.layers) {
        return;
    }
    blur_line(gid.x, gid.y, gid.z, 1, 0);
}

@compute @workgroup_size(8, 8, 1)
fn vertical(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.map_size || gid.y >= frame.map_size || gid.z >= settings.layers) {
        return;
    }
    blur_line(gid.x, gid.y, gid.z, 0, 1);
}
