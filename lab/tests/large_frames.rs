//! Large frames: every size is checked before any work (one line naming `resolution`, the size and
//! the device limit by its wgpu name, and nothing written), and per-pixel buffers past one storage
//! binding are bound by bands of rows with the same V bit for bit. The bands are tested at 128² on
//! a device whose bindings are capped, so a small frame takes the path a 4096² one takes.

mod common;
use common::{penumbra, temp_dir};
use penumbra::research::frame::{FrameOptions, Renderer};
use penumbra::research::gpu::size_plan::{Bound, DeviceBounds};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::gpu::{AdapterRequest, GpuContext};
use penumbra::research::methods::{sizes, Method};
use penumbra::research::scene::Scene;

/// Holds a 128² frame's shade-block scratch (22 test blocks of 2 KiB: 45,056 bytes) but not its
/// V (65,536 bytes) nor its lattice masks (655,360 bytes).
const CAP: u64 = 48 * 1024;

/// Holds four quads' comparison maps (16 KiB each), so the GPU-steered loop runs to max_level 2,
/// and V whole; not the masks.
const STEER_CAP: u64 = 64 * 1024;

fn capped() -> &'static GpuContext {
    static CTX: std::sync::OnceLock<GpuContext> = std::sync::OnceLock::new();
    CTX.get_or_init(|| {
        GpuContext::with_binding_cap(&AdapterRequest::default(), CAP)
            .expect("GPU test needs an adapter")
    })
}

fn steer_capped() -> &'static GpuContext {
    static CTX: std::sync::OnceLock<GpuContext> = std::sync::OnceLock::new();
    CTX.get_or_init(|| {
        GpuContext::with_binding_cap(&AdapterRequest::default(), STEER_CAP)
            .expect("GPU test needs an adapter")
    })
}

fn scene() -> Scene {
    scene_with_maps(256)
}

/// `default` at 128² with maps of `size`² (msm's moments, 16 bytes a texel, must fit the cap).
fn scene_with_maps(size: u32) -> Scene {
    let size = size.to_string();
    let sets = [("resolution", "128"), ("shadow_map_size", size.as_str())]
        .map(|(k, v)| (k.to_string(), v.to_string()));
    Scene::load("default", &sets).unwrap()
}

/// V and the read-backs the method needed (0: the GPU-steered loop).
fn frame(ctx: &GpuContext, scene: &Scene, method: &Method) -> (Vec<f32>, u32) {
    let mut r = Renderer::new(ctx, scene, method).unwrap();
    let f = r
        .frame(FrameOptions {
            mode: TimingMode::Frame,
            pictures: false,
        })
        .unwrap();
    (f.visibility, f.output.syncs)
}

#[test]
fn banded_frames_equal_whole_ones_bit_for_bit() {
    let scene = scene();
    assert_eq!(capped().limits().max_storage_buffer_binding_size, CAP);
    // The bands the frame driver takes: V's 512-byte rows (96 in 48 KiB), or the masks' 5,120-byte
    // rows (9 or 12 fit; whole tiles: 8).
    let small_maps = scene_with_maps(32);
    for (ctx, spec, rows, steered) in [
        (capped(), "hard", 96, false),
        (capped(), "pcf:kernel=poisson", 96, false),
        (capped(), "pcf:kernel=rotated", 96, false),
        (capped(), "pcss", 96, false),
        (capped(), "msm", 96, false),
        (capped(), "regular:n=5", 96, false),
        (capped(), "regular:n=4,layout=centred", 96, false),
        (capped(), "adaptive:preset=seed", 8, false),
        (capped(), "adaptive:preset=balanced", 8, false),
        (steer_capped(), "adaptive:max_level=2,steer=gpu", 8, true),
    ] {
        let method = Method::parse(spec, &[]).unwrap();
        let scene = if spec == "msm" { &small_maps } else { &scene };
        assert_eq!(
            sizes::band_rows(scene, &method, &ctx.limits()),
            rows,
            "{spec}"
        );
        assert_eq!(
            sizes::band_rows(scene, &method, &common::gpu().limits()),
            0,
            "{spec}: one band on the real limit"
        );
        let (whole, _) = frame(common::gpu(), scene, &method);
        let (banded, syncs) = frame(ctx, scene, &method);
        // Adaptive's waiting loop reads each level back; the steered one none.
        if spec.starts_with("adaptive") {
            assert_eq!(syncs == 0, steered, "{spec}: {syncs} read-backs");
        }
        // Not a blank image: lit, shadowed (or background) and, for the soft methods, penumbra pixels.
        let lit = whole.iter().filter(|&&v| v == 1.0).count();
        let penumbra = whole.iter().filter(|&&v| v > 0.0 && v < 1.0).count();
        assert!(
            lit > 1000 && whole.len() - lit > 1000,
            "{spec}: {lit} lit pixels"
        );
        assert!(
            spec == "hard" || penumbra > 100,
            "{spec}: only {penumbra} penumbra pixels"
        );
        println!(
            "{spec}: {} bands, {lit} lit, {penumbra} penumbra pixels, V identical",
            128u32.div_ceil(rows)
        );
        let differ = whole
            .iter()
            .zip(&banded)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(
            differ,
            0,
            "{spec}: {differ} of {} pixels differ between {} bands and one",
            whole.len(),
            128u32.div_ceil(rows)
        );
    }
}

#[test]
fn methods_that_bind_whole_are_refused_on_the_capped_device() {
    let scene = scene();
    for spec in ["ssao", "env-shadowmaps", "adaptive:scope=local"] {
        let e = Renderer::new(capped(), &scene, &Method::parse(spec, &[]).unwrap())
            .err()
            .unwrap_or_else(|| panic!("{spec} built"))
            .to_string();
        assert!(
            e.starts_with("resolution = 128 (128x128): ")
                && e.ends_with("over this device's max_storage_buffer_binding_size 49152"),
            "{spec}: {e}"
        );
        assert!(!e.contains('\n'), "{e}");
    }
}

/// The plan's sizes are the sizes of the buffers the renderer created, so the check cannot drift
/// from the allocation.
#[test]
fn the_plan_matches_the_buffers_created() {
    let scene = scene();
    for (ctx, spec, expected) in [
        (common::gpu(), "hard", 2),
        (capped(), "regular:n=5", 2),
        (common::gpu(), "adaptive:preset=seed", 6),
        (capped(), "adaptive:preset=balanced", 6),
        (common::gpu(), "adaptive:scope=local", 8),
    ] {
        let method = Method::parse(spec, &[]).unwrap();
        let plan = sizes::plan(&scene, &method, &ctx.limits(), false);
        let created = Renderer::new(ctx, &scene, &method).unwrap().buffer_sizes();
        assert_eq!(created.len(), expected, "{spec}: {created:?}");
        for (label, bytes) in &created {
            let need = plan
                .needs
                .iter()
                .find(|n| &n.what == label && n.bound != Bound::TextureSide)
                .unwrap_or_else(|| panic!("{spec}: `{label}` is not in the plan"));
            assert_eq!(need.amount, *bytes, "{spec}: `{label}`");
        }
    }
}

fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// `render` and `compare` at 16384²: one line naming `resolution`, the size and the limit, exit 1,
/// and the output folder as it was (a user's file, no staging folder, no set).
#[test]
fn oversized_frames_are_refused_before_any_work() {
    for (case, args) in [
        ("render-hard", vec!["render", "--method", "hard"]),
        (
            "render-adaptive",
            vec!["render", "--method", "adaptive:preset=balanced"],
        ),
        ("render-pcss", vec!["render", "--method", "pcss"]),
        ("compare", vec!["compare", "--methods", "hard,adaptive"]),
    ] {
        let out = temp_dir(&format!("large_frames_{case}"));
        std::fs::write(out.join("notes.txt"), "mine").unwrap();
        let before = listing(&out);
        let mut all = args.clone();
        all.extend([
            "--scene",
            "default",
            "--set",
            "resolution=16384",
            "--out",
            out.to_str().unwrap(),
        ]);
        let started = std::time::Instant::now();
        let r = penumbra(&all);
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{case}: {stderr}");
        let lines: Vec<&str> = stderr.lines().collect();
        assert_eq!(lines.len(), 1, "{case}: {stderr}");
        assert!(
            lines[0].starts_with("error: resolution = 16384 (16384x16384): "),
            "{case}: {}",
            lines[0]
        );
        // The G-buffer's 4 GiB read-back is the first size past a limit on any device whose
        // buffers stop below 4 GiB; otherwise the host memory.
        assert!(
            lines[0].contains("needs 4294967296 bytes, over this device's max_buffer_size")
                || lines[0].contains("MemAvailable"),
            "{case}: {}",
            lines[0]
        );
        assert!(
            started.elapsed().as_secs() < 60,
            "{case}: refused only after {:?}",
            started.elapsed()
        );
        assert_eq!(listing(&out), before, "{case}: --out changed");
        assert_eq!(
            std::fs::read_to_string(out.join("notes.txt")).unwrap(),
            "mine"
        );
    }
}

/// 6000² on lavapipe's 128 MiB bindings: V (144,000,000 bytes) passes one binding. Methods whose
/// passes bind V whole are refused with the limit; the banded ones pass.
#[test]
fn a_6000_frame_is_refused_only_where_v_is_bound_whole() {
    let sets = [("resolution", "6000")].map(|(k, v)| (k.to_string(), v.to_string()));
    let scene = Scene::load("default", &sets).unwrap();
    let limits = wgpu::Limits {
        max_storage_buffer_binding_size: 134_217_728,
        max_buffer_size: 2_147_483_647,
        max_texture_dimension_2d: 16384,
        ..Default::default()
    };
    for (spec, refused) in [
        ("hard", false),
        ("regular:n=17", false),
        ("adaptive:preset=seed", false),
        ("pcss", false),
        ("msm", false),
        ("ssao", true),
        ("adaptive:scope=local", true),
    ] {
        let plan = sizes::plan(&scene, &Method::parse(spec, &[]).unwrap(), &limits, false);
        match plan.check(
            &DeviceBounds {
                limits: limits.clone(),
                largest_heap: None,
            },
            None,
        ) {
            Ok(()) => assert!(!refused, "{spec} passed"),
            Err(e) => {
                assert!(refused, "{spec}: {e}");
                assert_eq!(
                    e.to_string(),
                    "resolution = 6000 (6000x6000): visibility needs 144000000 bytes, over this device's max_storage_buffer_binding_size 134217728"
                );
            }
        }
    }
}
