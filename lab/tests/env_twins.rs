//! The environment kernels equal their CPU twins: env_trace (BVH traversal, per pixel and per
//! vertex), env_vertex_interp (barycentric interpolation), env_count (counting with atomics),
//! env_split (splitting), env_shadowmaps (median-cut maps, the pcf family's filters) and ssao.
//! Counts are compared exactly; V within float rounding of the same sums.

mod common;
use penumbra::research::frame::{self, FrameOptions};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::environment::{
    pixels as env_pixels, shadowmaps as env_shadowmaps,
};
use penumbra::research::methods::{ssao, Method};
use penumbra::research::scene::Scene;
use penumbra::research::stages::twin;
use std::path::Path;

/// A 64x32 sky: a gradient, dark below the horizon, and a 2x2 "sun" of 2000 at (u, v) ≈ (0.3, 0.25).
fn write_sky(dir: &Path) {
    let img = image::Rgb32FImage::from_fn(64, 32, |x, y| {
        let sun = (19..21).contains(&x) && (7..9).contains(&y);
        let l = if sun {
            2000.0
        } else if y < 16 {
            0.5 + 0.04 * y as f32
        } else {
            0.05
        };
        image::Rgb([l, l * 0.9, l * 0.8])
    });
    img.save_with_format(dir.join("sky.exr"), image::ImageFormat::OpenExr)
        .unwrap();
}

fn scene(dir: &Path, size: u32) -> Scene {
    let text = format!(
        "name = \"envtest\"\n[camera]\neye = [0.0, 7.0, 9.0]\ntarget = [0.0, 0.5, 0.0]\nfov_y_deg = 45.0\n\n\
         [environment]\npanorama = \"sky.exr\"\nrotation_deg = 30.0\n\n\
         [render]\nwidth = {size}\nheight = {size}\nshadow_map_size = 128\n\n\
         [[mesh]]\nbuiltin = \"plane\"\nscale = [12.0, 1.0, 12.0]\n\n\
         [[mesh]]\nbuiltin = \"box\"\ntranslate = [0.0, 1.0, 0.0]\nrotate_deg = [0.0, 30.0, 0.0]\nscale = [2.0, 2.0, 1.0]\n\n\
         [[mesh]]\nbuiltin = \"sphere\"\nsegments = 12\ntranslate = [2.5, 0.8, 1.5]\nscale = 1.6\n"
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, &text).unwrap();
    Scene::load(path.to_str().unwrap(), &[]).unwrap()
}

fn setup(name: &str) -> Scene {
    let dir = common::temp_dir(name);
    write_sky(&dir);
    scene(&dir, 40)
}

fn options() -> FrameOptions {
    FrameOptions {
        mode: TimingMode::Frame,
        pictures: false,
    }
}

#[test]
fn env_trace_and_ssao_equal_their_twins() {
    let ctx = common::gpu();
    let sc = setup("env_twins_trace");
    for spec in [
        "env-pixels:res=16x8",
        "env-pixels:res=64x32",
        "env-pixels:res=32x16,ssao=on,ao_samples=12",
    ] {
        let (r, c): (_, env_pixels::EnvTraceBuffers) =
            common::inspected(ctx, &sc, &Method::parse(spec, &[]).unwrap(), options());
        let (v, blocked) =
            twin::env_trace::env_trace(&c.params, &r.gbuffer, &c.lights, &c.ao, &c.bvh);
        let geometry: Vec<usize> = (0..v.len()).filter(|&i| r.gbuffer.is_geometry(i)).collect();
        let mismatched = geometry
            .iter()
            .filter(|&&i| blocked[i] != c.blocked[i])
            .count();
        let worst = geometry
            .iter()
            .map(|&i| (v[i].clamp(0.0, 1.0) - r.visibility[i]).abs())
            .fold(0.0f32, f32::max);
        let total_blocked: u64 = geometry.iter().map(|&i| c.blocked[i] as u64).sum();
        let partial = geometry
            .iter()
            .filter(|&&i| r.visibility[i] > 0.02 && r.visibility[i] < 0.98)
            .count();
        println!("{spec}: {} lights, {} geometry pixels, {total_blocked} blocked rays, {partial} partly lit, max |GPU - twin| V {worst:e}", c.lights.len(), geometry.len());
        assert_eq!(
            mismatched, 0,
            "{spec}: blocked-ray counts differ from the twin in {mismatched} pixels"
        );
        assert!(worst <= 1e-5, "{spec}: V differs from the twin by {worst}");
        assert!(
            total_blocked > 1000 && partial > 50,
            "{spec}: too little shadow for the test to prove anything"
        );
        if spec.contains("ssao") {
            let (ao_ctx, a): (_, ssao::SsaoBuffers) = common::inspected(
                ctx,
                &sc,
                &Method::parse("ssao:ao_samples=12", &[]).unwrap(),
                options(),
            );
            let (ao, occluded) = twin::ssao::ssao(&a.params, &a.camera, &a.kernel, &ao_ctx.gbuffer);
            let differ = geometry
                .iter()
                .filter(|&&i| occluded[i] != a.occluded[i])
                .count();
            let occluding = geometry.iter().filter(|&&i| a.occluded[i] > 0).count();
            println!(
                "ssao: {occluding} pixels with an occluded sample, {differ} differ from the twin"
            );
            assert_eq!(
                differ, 0,
                "ssao: occluded counts differ from the twin in {differ} pixels"
            );
            assert!(
                occluding > 10,
                "ssao finds no crease: the test proves nothing"
            );
            for &i in &geometry {
                assert_eq!(ao[i], a.ao[i], "pixel {i}: AO");
                assert_eq!(
                    a.ao[i], ao_ctx.visibility[i],
                    "pixel {i}: the ssao method's V is its AO"
                );
            }
        }
    }
}

#[test]
fn env_count_and_env_split_equal_their_twins_at_every_level() {
    let ctx = common::gpu();
    let sc = setup("env_twins_adaptive");
    let method = Method::parse("env-adaptive:cells=4x2,max_level=3,contrast=3", &[]).unwrap();
    let (r, c): (_, env_pixels::EnvTraceBuffers) = common::inspected(ctx, &sc, &method, options());
    assert!(c.levels.len() >= 3, "only {} levels ran", c.levels.len());
    let mut splits = 0;
    for (level, l) in c.levels.iter().enumerate() {
        let counts =
            twin::env_count::env_count(&l.params, &r.gbuffer, &l.corners, &l.cells, &c.bvh);
        let counted = level < l.params.max_level as usize;
        if counted {
            assert_eq!(
                counts, l.counts,
                "level {level}: env_count differs from its twin"
            );
        } else {
            assert!(
                l.counts.iter().all(|&x| x == 0),
                "level {level}: the last level is not counted"
            );
        }
        let (next, leaves) =
            twin::env_split::env_split(&l.params, &l.cells, &l.counts, &l.cell_power);
        assert_eq!(
            next, l.next,
            "level {level}: env_split's children differ from its twin"
        );
        assert_eq!(
            leaves, l.leaves,
            "level {level}: env_split's leaves differ from its twin"
        );
        println!(
            "level {level}: {} cells, counts {:?}, {} children, {} leaves",
            l.cells.len(),
            &l.counts[..l.counts.len().min(16)],
            next.len(),
            leaves.len()
        );
        splits += next.len() / 4;
        if counted && level == 0 {
            assert!(
                l.counts.iter().any(|&x| x > 0),
                "no cell's corners disagree at level 0: the scene casts no shadow"
            );
        }
    }
    assert!(splits > 4, "only {splits} splits: the test proves little");
    let (v, blocked) = twin::env_trace::env_trace(&c.params, &r.gbuffer, &c.lights, &c.ao, &c.bvh);
    for i in (0..v.len()).filter(|&i| r.gbuffer.is_geometry(i)) {
        assert_eq!(blocked[i], c.blocked[i], "pixel {i}: blocked rays");
        assert!(
            (v[i].clamp(0.0, 1.0) - r.visibility[i]).abs() <= 1e-5,
            "pixel {i}: V"
        );
    }
}

/// The barycentrics raster sees what the G-buffer sees: the same pixels are geometry, and each
/// pixel's barycentrics rebuild its G-buffer position from its triangle's corners.
#[test]
fn barycentrics_rebuild_the_gbuffer() {
    let ctx = common::gpu();
    let sc = setup("env_twins_bary");
    let (r, c): (_, env_pixels::EnvTraceBuffers) = common::inspected(
        ctx,
        &sc,
        &Method::parse("env-pixels:res=8x4,at=vertex", &[]).unwrap(),
        options(),
    );
    let v = c.vertex.expect("per-vertex buffers");
    let diag = sc.bounds.diagonal();
    let (mut covered, mut worst) = (0, 0.0f32);
    for (i, id) in v.ids.iter().enumerate() {
        assert_eq!(
            id[0] != 0,
            r.gbuffer.is_geometry(i),
            "pixel {i}: ids and G-buffer disagree on coverage"
        );
        if id[0] == 0 {
            continue;
        }
        covered += 1;
        let t = (id[0] - 1) as usize * 3;
        let (b1, b2) = (f32::from_bits(id[1]), f32::from_bits(id[2]));
        let b = [1.0 - b1 - b2, b1, b2];
        assert!(
            b.iter().all(|&x| (-1e-3..=1.0 + 1e-3).contains(&x)),
            "pixel {i}: barycentrics {b:?}"
        );
        let p = (0..3).fold(glam::Vec3::ZERO, |acc, k| {
            acc + b[k] * glam::Vec3::from(sc.vertices[sc.indices[t + k] as usize].position)
        });
        worst =
            worst.max((p - glam::Vec3::from_slice(&r.gbuffer.position[i][..3])).length() / diag);
    }
    println!("{covered} covered pixels, max |Σ b·p − G-buffer position| = {worst:e} × diagonal");
    assert!(covered > 500, "only {covered} pixels covered");
    assert!(
        worst < 1e-4,
        "barycentrics miss the G-buffer position by {worst} diagonals"
    );
}

/// env_trace's `vertex` entry point counts the same blocked rays at every vertex as its twin, and
/// env_vertex_interp spreads V over the pixels as its twin does.
#[test]
fn env_trace_vertex_and_interp_equal_their_twins() {
    let ctx = common::gpu();
    let sc = setup("env_twins_vertex");
    for spec in [
        "env-pixels:res=16x8,at=vertex",
        "env-pixels:res=64x32,at=vertex",
        "env-pixels:res=16x8,at=vertex,ssao=on",
    ] {
        let (r, c): (_, env_pixels::EnvTraceBuffers) =
            common::inspected(ctx, &sc, &Method::parse(spec, &[]).unwrap(), options());
        let v = c.vertex.as_ref().expect("per-vertex buffers");
        assert_eq!(
            r.output.record["vertices_traced"],
            sc.vertices.len(),
            "{spec}: record"
        );
        let (vv, blocked) =
            twin::env_trace::env_trace_vertices(&c.params, &sc.vertices, &c.lights, &c.bvh);
        assert_eq!(blocked, v.blocked, "{spec}: blocked rays per vertex");
        let worst_vertex = vv
            .iter()
            .zip(&v.visibility)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        let partial = v
            .visibility
            .iter()
            .filter(|&&x| x > 0.02 && x < 0.98)
            .count();
        let pixels = twin::env_vertex_interp::env_vertex_interp(
            &c.params,
            &v.ids,
            &sc.indices,
            &v.visibility,
            &c.ao,
        );
        let worst_pixel = (0..pixels.len())
            .filter(|&i| r.gbuffer.is_geometry(i))
            .map(|i| (pixels[i].clamp(0.0, 1.0) - r.visibility[i]).abs())
            .fold(0.0f32, f32::max);
        println!(
            "{spec}: {} vertices, {} blocked rays, {partial} partly lit, max |GPU − twin| V per vertex {worst_vertex:e}, per pixel {worst_pixel:e}",
            sc.vertices.len(),
            blocked.iter().map(|&b| b as u64).sum::<u64>()
        );
        assert!(
            partial > 10,
            "{spec}: only {partial} partly lit vertices, the test would prove little"
        );
        assert!(
            worst_vertex <= 1e-6,
            "{spec}: V per vertex differs from the twin by {worst_vertex}"
        );
        assert!(
            worst_pixel <= 1e-6,
            "{spec}: interpolated V differs from the twin by {worst_pixel}"
        );
    }
}

#[test]
fn env_shadowmaps_equals_its_twin() {
    let ctx = common::gpu();
    let sc = setup("env_twins_maps");
    // (spec, share of pixels allowed off by more than `tol`, tol), as the pcf twin test: rotated
    // taps come from sin and cos, whose last bits may differ; the comparison sampler (bilinear)
    // filters with the device's own weights.
    let specs: [(&str, f64, f32); 6] = [
        ("env-shadowmaps:k=8,pcf_radius=0", 0.0, 1e-5),
        ("env-shadowmaps:k=16,pcf_radius=2,ssao=on", 0.0, 1e-5),
        ("env-shadowmaps:k=8,filter=poisson,pcf_radius=2", 0.0, 1e-5),
        (
            "env-shadowmaps:k=8,filter=stratified,taps=8,pcf_radius=2",
            0.0,
            1e-5,
        ),
        (
            "env-shadowmaps:k=8,filter=rotated,pcf_radius=2",
            0.002,
            1e-5,
        ),
        ("env-shadowmaps:k=8,filter=bilinear", 0.0, 1e-4),
    ];
    for (spec, share, tol) in specs {
        let (r, c): (_, env_shadowmaps::EnvShadowmapsBuffers) =
            common::inspected(ctx, &sc, &Method::parse(spec, &[]).unwrap(), options());
        let filter = twin::env_shadowmaps::Filter {
            settings: &c.filter,
            disk: &c.disk,
        };
        let v = twin::env_shadowmaps::env_shadowmaps(
            &c.frame,
            &c.params,
            filter,
            twin::env_shadowmaps::LightMaps {
                samples: &c.samples,
                maps: &c.maps,
            },
            &c.lights,
            &c.ao,
            &r.gbuffer,
        );
        let geometry: Vec<usize> = (0..v.len()).filter(|&i| r.gbuffer.is_geometry(i)).collect();
        let diff = |i: usize| (v[i].clamp(0.0, 1.0) - r.visibility[i]).abs();
        let worst = geometry.iter().map(|&i| diff(i)).fold(0.0f32, f32::max);
        let off = geometry.iter().filter(|&&i| diff(i) > tol).count();
        let shadowed = geometry.iter().filter(|&&i| r.visibility[i] < 0.98).count();
        println!("{spec}: {} maps, {shadowed} pixels under 0.98, {off}/{} off by > {tol:e}, max |GPU - twin| {worst:e}", c.maps.len(), geometry.len());
        assert!(shadowed > 30, "{spec}: no shadow");
        assert!(
            off as f64 <= share * geometry.len() as f64,
            "{spec}: {off} pixels differ from the twin by more than {tol} (max {worst})"
        );
    }
}

/// The default filter is the box the method always had: the same V as the explicit box spelling,
/// and a disk pattern changes it.
#[test]
fn env_shadowmaps_default_filter_is_box() {
    let ctx = common::gpu();
    let sc = setup("env_twins_box");
    let run = |spec: &str| {
        frame::render(ctx, &sc, &Method::parse(spec, &[]).unwrap(), options())
            .unwrap()
            .visibility
    };
    let default = run("env-shadowmaps:k=8");
    assert_eq!(
        default,
        run("env-shadowmaps:k=8,filter=box,taps=3,pcf_radius=1")
    );
    let poisson = run("env-shadowmaps:k=8,filter=poisson");
    let changed = default
        .iter()
        .zip(&poisson)
        .filter(|(a, b)| (*a - *b).abs() > 1e-3)
        .count();
    assert!(changed > 10, "poisson taps changed only {changed} pixels");
}

#[test]
fn environment_methods_need_an_environment() {
    let ctx = common::gpu();
    let sc = Scene::parse(&common::random_scene_toml(5, 32, 64), "random", None, &[]).unwrap();
    for spec in ["env-pixels", "env-shadowmaps", "env-adaptive"] {
        let e = frame::render(ctx, &sc, &Method::parse(spec, &[]).unwrap(), options())
            .err()
            .expect("no environment")
            .to_string();
        assert!(
            e.contains(spec) && e.contains("has no [environment]"),
            "{spec}: {e}"
        );
    }
}

#[test]
fn environment_command_writes_the_set_with_charts_pictures_and_table() {
    let dir = common::temp_dir("env_command");
    write_sky(&dir);
    scene(&dir, 32);
    let out = dir.join("out");
    let cache = dir.join("cache");
    let scene_path = dir.join("scene.toml");
    let o = common::penumbra_env(
        &[
            "environment",
            "--scenes",
            scene_path.to_str().unwrap(),
            "--methods",
            "env-pixels:res=16x8,env-shadowmaps:k=4,env-adaptive:max_level=2",
            "--samples",
            "4",
            "--repeats",
            "1",
            "--out",
            out.to_str().unwrap(),
        ],
        &[("PENUMBRA_CACHE", cache.to_str().unwrap())],
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "environment failed: {stderr}");
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(
        html.contains("Environment lighting (seed 002)") && html.contains("data:image/png;base64"),
        "no environment section"
    );
    let table = std::fs::read_to_string(out.join("environment.md")).unwrap();
    assert!(
        table.contains("`env-shadowmaps:k=4`")
            && table.contains("env-adaptive")
            && table.contains("Reference standard error"),
        "{table}"
    );
    for f in [
        "charts/env_error_vs_time.svg",
        "charts/env_error_vs_samples.png",
        "results.jsonl",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let pictures: Vec<_> = std::fs::read_dir(out.join("envtest/pictures"))
        .unwrap()
        .collect();
    assert_eq!(
        pictures.len(),
        3,
        "one panorama picture per environment method"
    );
}
