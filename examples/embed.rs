//! Embedding penumbra in a program that owns its wgpu device, as a game engine or editor would.
//!
//! It creates the wgpu instance, adapter and device itself, builds the shipped `analytic-square`
//! scene (scenes/analytic-square.toml: a 4×4 square occluder 4 above a 30×30 ground, under a 4×4
//! light 10 above it) from raw meshes, renders V through penumbra's API and writes it:
//!
//! ```sh
//! cargo run --release --example embed -- [METHOD] [SIZE] [OUT_DIR]
//! # defaults: adaptive:preset=balanced 256 embed-out → embed-out/visibility.exr and .png
//! ```
//!
//! Its V equals `penumbra render --scene analytic-square --method METHOD --set resolution=SIZE`'s
//! value for value (lab/tests/embed_render.rs checks it; tests/embed_example.rs runs it against the engine alone).

use penumbra::{Camera, Mesh, RectLight, SceneBuilder, ShadowScene, Shadows, Visibility};

/// The app's own device: the first high-performance adapter of the primary backends
/// (`WGPU_BACKEND` overrides them), with the limits penumbra needs on top of the adapter's.
pub fn app_device() -> Result<(wgpu::Adapter, wgpu::Device, wgpu::Queue), String> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
    let instance = wgpu::Instance::new(desc);
    let options = wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        ..Default::default()
    };
    let adapter = pollster::block_on(instance.request_adapter(&options))
        .map_err(|e| format!("no adapter: {e}"))?;
    let descriptor = wgpu::DeviceDescriptor {
        label: Some("app device"),
        required_features: adapter.features() & penumbra::OPTIONAL_FEATURES,
        required_limits: penumbra::required_limits(adapter.limits()),
        ..Default::default()
    };
    let (device, queue) = pollster::block_on(adapter.request_device(&descriptor))
        .map_err(|e| format!("request_device: {e}"))?;
    Ok((adapter, device, queue))
}

/// A unit square in the xz plane, facing +y, scaled and lifted: the scene format's `plane`.
fn plane(half: f32, height: f32) -> Mesh {
    let positions = vec![
        [-half, height, half],
        [half, height, half],
        [half, height, -half],
        [-half, height, -half],
    ];
    Mesh::new(positions, vec![0, 1, 2, 0, 2, 3]).with_normals(vec![[0.0, 1.0, 0.0]; 4])
}

/// scenes/analytic-square.toml at `size`×`size` pixels.
pub fn analytic_square(size: u32) -> penumbra::Result<ShadowScene> {
    SceneBuilder::new(
        Camera::look_at([0.0, 16.0, 14.0], [0.0, 0.0, -1.0], 50.0),
        RectLight {
            center: [0.0, 10.0, 0.0],
            edge_u: [4.0, 0.0, 0.0],
            edge_v: [0.0, 0.0, 4.0],
        },
    )
    .mesh(plane(15.0, 0.0))
    .mesh(plane(2.0, 4.0).with_albedo([0.9, 0.3, 0.2]))
    .resolution(size, size)
    .set("cull", "none")
    .build()
}

/// V of `method` on the analytic square at `size`², on the app's own device; also the adapter's name.
pub fn render(method: &str, size: u32) -> Result<(Visibility, String), String> {
    let (adapter, device, queue) = app_device()?;
    let shadows = Shadows::new(&adapter, &device, &queue).map_err(|e| e.to_string())?;
    let scene = analytic_square(size).map_err(|e| e.to_string())?;
    let mut renderer = shadows
        .renderer(&scene, method)
        .map_err(|e| e.to_string())?;
    let v = renderer.render().map_err(|e| e.to_string())?;
    Ok((v, adapter.get_info().name))
}

/// V as a 32-bit float EXR (gray in RGB, as `penumbra render` writes it) and a 16-bit PNG.
pub fn write(v: &Visibility, dir: &std::path::Path) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let at = |x: u32, y: u32| v.values[(y * v.width + x) as usize];
    let exr = image::Rgb32FImage::from_fn(v.width, v.height, |x, y| image::Rgb([at(x, y); 3]));
    let png = image::ImageBuffer::<image::Luma<u16>, _>::from_fn(v.width, v.height, |x, y| {
        image::Luma([(at(x, y).clamp(0.0, 1.0) * 65535.0).round() as u16])
    });
    for (name, result) in [
        ("visibility.exr", exr.save(dir.join("visibility.exr"))),
        ("visibility.png", png.save(dir.join("visibility.png"))),
    ] {
        result.map_err(|e| format!("{}: {e}", dir.join(name).display()))?;
    }
    Ok(())
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let method = args
        .first()
        .map_or("adaptive:preset=balanced", String::as_str);
    let size = args
        .get(1)
        .map_or(Ok(256), |s| s.parse::<u32>())
        .unwrap_or_else(|_| {
            eprintln!("SIZE must be a positive integer");
            std::process::exit(2)
        });
    let out = std::path::PathBuf::from(args.get(2).map_or("embed-out", String::as_str));
    let done = render(method, size).and_then(|(v, adapter)| {
        write(&v, &out)?;
        let lit = v.values.iter().filter(|&&x| x > 0.0).count();
        println!("{}: {method} on analytic-square, {size}x{size}, {} shadow maps, {lit} pixels lit, on {adapter}", out.display(), v.shadow_maps);
        Ok(())
    });
    if let Err(e) = done {
        eprintln!("embed: {e}");
        std::process::exit(1);
    }
}
