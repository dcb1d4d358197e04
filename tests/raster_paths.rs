//! `raster = compute` against `raster = hardware` through every method: the same scene, the same
//! frame, V from maps rasterized by the compute kernels (read through kernels/shared/maps_words.wgsl)
//! against V from the fixed-function raster (maps_plain.wgsl). The two rasters differ only at the
//! texels docs/gpu-frame.md §7 names (the 1/256-texel snap), so V must agree almost everywhere.

mod common;
use penumbra::frame::{FrameOptions, Renderer};
use penumbra::gpu::timing::TimingMode;
use penumbra::methods::{Family, Method, REGISTRY};
use penumbra::scene::Scene;

fn scene(text: &str, dir: &std::path::Path, raster: &str, extra: &[(&str, &str)]) -> Scene {
    let mut sets = vec![("raster".to_string(), raster.to_string())];
    sets.extend(extra.iter().map(|(k, v)| (k.to_string(), v.to_string())));
    Scene::parse(text, "random-7", Some(dir), &sets).unwrap()
}

#[test]
fn every_method_renders_the_same_v_from_compute_maps() {
    let ctx = common::gpu();
    let dir = common::temp_dir("raster_paths");
    image::Rgb32FImage::from_fn(64, 32, |x, y| image::Rgb(if (x, y) == (18, 8) { [800.0; 3] } else { [0.6; 3] })).save_with_format(dir.join("sky.exr"), image::ImageFormat::OpenExr).unwrap();
    let plain = common::random_scene_toml(7, 64, 128);
    let lit = format!("{plain}\n[environment]\npanorama = \"sky.exr\"\n");
    let mut specs: Vec<String> = REGISTRY.iter().map(|m| m.name.to_string()).collect();
    specs.extend(["regular:n=4", "adaptive:scope=local", "adaptive:scope=local,cull=on", "adaptive:preset=balanced", "adaptive:steer=cpu", "env-shadowmaps:k=4"].map(String::from));
    let options = FrameOptions { mode: TimingMode::Frame, pictures: false };
    let hybrid = [("maps", "hybrid"), ("hybrid.base", "128"), ("hybrid.levels", "1")];
    let mut cases: Vec<(String, &[(&str, &str)])> = specs.iter().map(|s| (s.clone(), &[][..])).collect();
    cases.extend(["regular:n=3", "adaptive", "hard", "pcss"].map(|s| (format!("{s} (maps = hybrid)"), &hybrid[..])));
    let mut checked = 0;
    for (label, extra) in &cases {
        let spec = label.split(' ').next().unwrap();
        let method = Method::parse(spec, &[]).unwrap();
        // The environment methods other than env-shadowmaps rasterize no shadow maps.
        if method.family() == Family::Environment && !spec.starts_with("env-shadowmaps") {
            continue;
        }
        let text = if method.family() == Family::Environment { &lit } else { &plain };
        let [hw, cs] = ["hardware", "compute"].map(|r| {
            let s = scene(text, &dir, r, extra);
            let mut renderer = Renderer::new(ctx, &s, &method).unwrap_or_else(|e| panic!("{label}, raster = {r}: {e}"));
            assert_eq!(renderer.raster_name(), r, "{label}: the renderer's raster");
            let f = renderer.frame(options).unwrap();
            (f.visibility, f.gbuffer, f.output.shadow_maps)
        });
        assert_eq!(hw.2, cs.2, "{label}: maps");
        let geometry: Vec<usize> = (0..hw.0.len()).filter(|&i| hw.1.is_geometry(i)).collect();
        let shadowed = geometry.iter().filter(|&&i| hw.0[i] < 1.0).count();
        let exact = geometry.iter().filter(|&&i| hw.0[i] == cs.0[i]).count();
        // Filtered methods carry depth itself into V: the rasters' last-bit depth differences show.
        let differ = geometry.iter().filter(|&&i| (hw.0[i] - cs.0[i]).abs() > 1e-3).count();
        let worst = geometry.iter().map(|&i| (hw.0[i] - cs.0[i]).abs()).fold(0.0f32, f32::max);
        let mean = geometry.iter().map(|&i| (hw.0[i] - cs.0[i]).abs() as f64).sum::<f64>() / geometry.len() as f64;
        println!("{label}: {exact} of {} geometry pixels equal, {differ} differ by > 1e-3 ({shadowed} shadowed), mean |dV| {mean:.2e}, worst {worst:.3}", geometry.len());
        assert!(shadowed > 20, "{label}: only {shadowed} shadowed pixels");
        assert!(mean < 2e-3, "{label}: mean |dV| {mean:.2e} between the rasters");
        assert!((differ as f64) < 0.02 * geometry.len() as f64, "{label}: {differ} of {} pixels differ by > 1e-3", geometry.len());
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} cases compared");
}
