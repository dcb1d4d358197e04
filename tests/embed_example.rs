//! The embedding API and examples/embed.rs, against the engine alone: a camera move needs no
//! rebuild; a device that lacks a limit is refused by name. (That its V equals `penumbra render`'s,
//! value for value, is the lab's lab/tests/embed_render.rs: the binary is the lab's.)

mod common;

// The example's functions, compiled into this test (its `main` is unused here).
#[allow(dead_code)]
#[path = "../examples/embed.rs"]
mod embed;

use penumbra::{Camera, Shadows};

const SIZE: u32 = 64;

/// Channel 0 of an EXR.
fn read_exr(path: &std::path::Path) -> (u32, u32, Vec<f32>) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb32f();
    (
        img.width(),
        img.height(),
        img.pixels().map(|p| p[0]).collect(),
    )
}

#[test]
fn the_example_renders_and_writes_its_v() {
    let dir = common::temp_dir("embed_example");
    for (k, method) in ["hard", "adaptive:preset=balanced"].into_iter().enumerate() {
        let (v, _adapter) = embed::render(method, SIZE).unwrap_or_else(|e| panic!("{method}: {e}"));
        assert_eq!(
            (v.width, v.height, v.values.len()),
            (SIZE, SIZE, (SIZE * SIZE) as usize)
        );
        let ours = dir.join(format!("embed-{k}"));
        embed::write(&v, &ours).unwrap();
        let (w, h, written) = read_exr(&ours.join("visibility.exr"));
        assert_eq!((w, h), (SIZE, SIZE));
        assert_eq!(written, v.values, "{method}: the example's EXR holds its V");
    }
}

#[test]
fn a_camera_move_renders_as_a_renderer_built_for_that_camera() {
    let (adapter, device, queue) = embed::app_device().unwrap();
    let shadows = Shadows::new(&adapter, &device, &queue).unwrap();
    let moved = Camera::look_at([9.0, 12.0, 10.0], [1.0, 0.0, 0.0], 45.0);
    let scene = embed::analytic_square(SIZE).unwrap();
    let mut scene_moved = embed::analytic_square(SIZE).unwrap();
    scene_moved.set_camera(moved).unwrap();
    for method in ["regular:n=3", "adaptive:preset=balanced"] {
        let mut live = shadows.renderer(&scene, method).unwrap();
        let before = live.render().unwrap();
        let start = std::time::Instant::now();
        live.set_camera(&moved).unwrap();
        let after = live.render().unwrap();
        let moved_ms = start.elapsed().as_secs_f64() * 1e3;
        let start = std::time::Instant::now();
        let fresh = shadows
            .renderer(&scene_moved, method)
            .unwrap()
            .render()
            .unwrap();
        let fresh_ms = start.elapsed().as_secs_f64() * 1e3;
        assert_ne!(
            before.values, after.values,
            "{method}: the camera move changed nothing"
        );
        let differ = after
            .values
            .iter()
            .zip(&fresh.values)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(
            differ, 0,
            "{method}: {differ} pixels differ from a renderer built for the moved camera"
        );
        println!("{method}: moved camera equals a fresh renderer; frame after set_camera {moved_ms:.0} ms, new renderer + frame {fresh_ms:.0} ms");
    }
    // A camera that sees none of the meshes is refused when it is set, naming that camera.
    let mut r = shadows.renderer(&scene, "hard").unwrap();
    let away = Camera::look_at([0.0, 16.0, 14.0], [0.0, 40.0, 100.0], 20.0);
    let e = r
        .set_camera(&away)
        .expect_err("a camera looking away is refused")
        .to_string();
    assert!(
        e.contains("no mesh is visible") && e.contains("[0.0, 40.0, 100.0]"),
        "{e}"
    );
}

#[test]
fn the_texture_holds_the_cpu_values() {
    let (adapter, device, queue) = embed::app_device().unwrap();
    let shadows = Shadows::new(&adapter, &device, &queue).unwrap();
    let scene = embed::analytic_square(SIZE).unwrap();
    let mut r = shadows.renderer(&scene, "pcss").unwrap();
    let cpu = r.render().unwrap();
    let texture = r.render_to_texture().unwrap();
    assert_eq!(texture.format(), wgpu::TextureFormat::R32Float);
    // 64 texels × 4 bytes is one 256-byte row: no padding to strip.
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: (SIZE * SIZE * 4) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&Default::default());
    enc.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(SIZE * 4),
                rows_per_image: None,
            },
        },
        texture.size(),
    );
    queue.submit([enc.finish()]);
    buffer
        .slice(..)
        .map_async(wgpu::MapMode::Read, |r| r.unwrap());
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    let gpu: Vec<f32> =
        bytemuck::cast_slice(&buffer.slice(..).get_mapped_range().unwrap()).to_vec();
    assert_eq!(gpu, cpu.values);
}

/// A device on the example's adapter with exactly `limits` and no features.
fn device_with(limits: wgpu::Limits) -> (wgpu::Adapter, wgpu::Device, wgpu::Queue) {
    let (adapter, _, _) = embed::app_device().unwrap();
    let desc = wgpu::DeviceDescriptor {
        required_limits: limits,
        ..Default::default()
    };
    let (device, queue) = pollster::block_on(adapter.request_device(&desc)).unwrap();
    (adapter, device, queue)
}

#[test]
fn a_device_below_the_needs_is_refused_by_name_and_the_needs_suffice() {
    let (adapter, device, queue) = device_with(wgpu::Limits::default());
    let e = Shadows::new(&adapter, &device, &queue)
        .expect_err("WebGPU's default limits are refused")
        .to_string();
    assert!(
        e.contains("max_color_attachment_bytes_per_sample = 32 (needs 48"),
        "{e}"
    );
    println!("refused: {e}");

    // Exactly what required_limits asks for on top of WebGPU's downlevel defaults, no features
    // (so no INDIRECT_FIRST_INSTANCE, 256 array layers): every area-light method runs, and gives
    // the V it gives on the app's device with the adapter's limits.
    let (adapter, device, queue) =
        device_with(penumbra::required_limits(wgpu::Limits::downlevel_defaults()));
    let shadows = Shadows::new(&adapter, &device, &queue).unwrap();
    let (adapter, device, queue) = embed::app_device().unwrap();
    let full = Shadows::new(&adapter, &device, &queue).unwrap();
    let scene = embed::analytic_square(32).unwrap();
    // cascades takes the sun alone (lab/tests/cascades.rs); this scene's light is a rectangle.
    let specs = penumbra::research::methods::REGISTRY
        .iter()
        .filter(|m| {
            m.family != penumbra::research::methods::Family::Environment && m.name != "cascades"
        })
        .map(|m| m.name);
    for spec in specs.chain(["regular:n=17", "adaptive:scope=local"]) {
        let v = shadows
            .renderer(&scene, spec)
            .and_then(|mut r| r.render())
            .unwrap_or_else(|e| panic!("{spec}: {e}"));
        assert!(v.values.iter().any(|&x| x > 0.0), "{spec}: nothing lit");
        let want = full
            .renderer(&scene, spec)
            .and_then(|mut r| r.render())
            .unwrap();
        assert_eq!(
            v, want,
            "{spec}: the least device's V differs from the full device's"
        );
    }
}

#[test]
fn bad_input_is_refused_with_its_reason() {
    let (adapter, device, queue) = embed::app_device().unwrap();
    let shadows = Shadows::new(&adapter, &device, &queue).unwrap();
    let scene = embed::analytic_square(16).unwrap();
    let err = |r: penumbra::Result<penumbra::ShadowRenderer>| r.expect_err("refused").to_string();
    assert!(err(shadows.renderer(&scene, "env-pixels")).contains("rectangular area light"));
    assert!(err(shadows.renderer(&scene, "adaptive:p_m=x")).contains("p_m"));
    assert!(err(shadows.renderer(&scene, "nope")).contains("unknown method"));
    let build = |b: penumbra::SceneBuilder| b.build().expect_err("refused").to_string();
    let cam = Camera::look_at([0.0, 16.0, 14.0], [0.0, 0.0, -1.0], 50.0);
    let light = penumbra::RectLight {
        center: [0.0, 10.0, 0.0],
        edge_u: [4.0, 0.0, 0.0],
        edge_v: [0.0, 0.0, 4.0],
    };
    let ground = penumbra::Mesh::new(
        vec![
            [-15.0, 0.0, 15.0],
            [15.0, 0.0, 15.0],
            [15.0, 0.0, -15.0],
            [-15.0, 0.0, -15.0],
        ],
        vec![0, 1, 2, 0, 2, 3],
    );
    assert!(build(penumbra::SceneBuilder::new(cam, light)).contains("no mesh"));
    assert!(build(
        penumbra::SceneBuilder::new(cam, light)
            .mesh(ground.clone())
            .set("widht", "3")
    )
    .contains("unknown render setting"));
    let e = build(
        penumbra::SceneBuilder::new(cam, light)
            .mesh(ground.clone())
            .set("cull", "sideways"),
    );
    assert!(e.contains("sideways"), "{e}");
    assert!(build(
        penumbra::SceneBuilder::new(cam, light)
            .mesh(penumbra::Mesh::new(vec![[0.0; 3]], vec![0, 1, 2]))
    )
    .contains("out of range"));
    let flipped = penumbra::RectLight {
        edge_v: [0.0, 0.0, -4.0],
        ..light
    };
    assert!(
        build(penumbra::SceneBuilder::new(cam, flipped).mesh(ground))
            .contains("away from every mesh")
    );
}
