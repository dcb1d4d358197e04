//! `raster = compute` against `raster = hardware` through every method: the same scene, the same
//! frame, V from maps rasterized by the compute kernels (read through kernels/shared/maps_words.wgsl)
//! against V from the fixed-function raster (maps_plain.wgsl). The two rasters differ only at the
//! texels docs/gpu-frame.md §7 names (the 1/256-texel snap), so V must agree almost everywhere.

mod common;
use penumbra::research::frame::{FrameOptions, Renderer};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::{Family, Method, REGISTRY};
use penumbra::research::scene::Scene;

fn scene(text: &str, dir: &std::path::Path, raster: &str, extra: &[(&str, &str)]) -> Scene {
    let mut sets = vec![("raster".to_string(), raster.to_string())];
    sets.extend(extra.iter().map(|(k, v)| (k.to_string(), v.to_string())));
    Scene::parse(text, "random-7", Some(dir), &sets).unwrap()
}

#[test]
fn every_method_renders_the_same_v_from_compute_maps() {
    let ctx = common::gpu();
    let dir = common::temp_dir("raster_paths");
    image::Rgb32FImage::from_fn(64, 32, |x, y| {
        image::Rgb(if (x, y) == (18, 8) {
            [800.0; 3]
        } else {
            [0.6; 3]
        })
    })
    .save_with_format(dir.join("sky.exr"), image::ImageFormat::OpenExr)
    .unwrap();
    let plain = common::random_scene_toml(7, 64, 128);
    let lit = format!("{plain}\n[environment]\npanorama = \"sky.exr\"\n");
    // auto prices its maps by the raster's time unless told otherwise; by texels it chooses alike
    // under both rasters.
    let mut specs: Vec<String> = REGISTRY
        .iter()
        .map(|m| {
            if m.name == "auto" {
                "auto:cost=texels".to_string()
            } else {
                m.name.to_string()
            }
        })
        .collect();
    specs.extend(
        [
            "cascades:filter=pcf",
            "regular:n=4",
            "adaptive:scope=local",
            "adaptive:scope=local,cull=on",
            "adaptive:preset=balanced",
            "adaptive:steer=cpu",
            "env-shadowmaps:k=4",
        ]
        .map(String::from),
    );
    let options = FrameOptions {
        mode: TimingMode::Frame,
        pictures: false,
    };
    let hybrid = [
        ("maps", "hybrid"),
        ("hybrid.base", "128"),
        ("hybrid.levels", "1"),
    ];
    let mut cases: Vec<(String, &[(&str, &str)])> =
        specs.iter().map(|s| (s.clone(), &[][..])).collect();
    cases.extend(
        ["regular:n=3", "adaptive", "hard", "pcss"]
            .map(|s| (format!("{s} (maps = hybrid)"), &hybrid[..])),
    );
    let mut checked = 0;
    for (label, extra) in &cases {
        let spec = label.split(' ').next().unwrap();
        let method = Method::parse(spec, &[]).unwrap();
        // The environment methods other than env-shadowmaps rasterize no shadow maps.
        if method.family() == Family::Environment && !spec.starts_with("env-shadowmaps") {
            continue;
        }
        // cascades takes the sun alone: the same scene under a sun.
        let sun = common::with_sun(&plain);
        let text = if method.family() == Family::Environment {
            &lit
        } else if spec.starts_with("cascades") {
            &sun
        } else {
            &plain
        };
        let [hw, cs] = ["hardware", "compute"].map(|r| {
            let s = scene(text, &dir, r, extra);
            let mut renderer = Renderer::new(ctx, &s, &method)
                .unwrap_or_else(|e| panic!("{label}, raster = {r}: {e}"));
            assert_eq!(renderer.raster_name(), r, "{label}: the renderer's raster");
            let f = renderer.frame(options).unwrap();
            (f.visibility, f.gbuffer, f.output.shadow_maps)
        });
        assert_eq!(hw.2, cs.2, "{label}: maps");
        let geometry: Vec<usize> = (0..hw.0.len()).filter(|&i| hw.1.is_geometry(i)).collect();
        let shadowed = geometry.iter().filter(|&&i| hw.0[i] < 1.0).count();
        let exact = geometry.iter().filter(|&&i| hw.0[i] == cs.0[i]).count();
        // Filtered methods carry depth itself into V: the rasters' last-bit depth differences show.
        let differ = geometry
            .iter()
            .filter(|&&i| (hw.0[i] - cs.0[i]).abs() > 1e-3)
            .count();
        let worst = geometry
            .iter()
            .map(|&i| (hw.0[i] - cs.0[i]).abs())
            .fold(0.0f32, f32::max);
        let mean = geometry
            .iter()
            .map(|&i| (hw.0[i] - cs.0[i]).abs() as f64)
            .sum::<f64>()
            / geometry.len() as f64;
        println!("{label}: {exact} of {} geometry pixels equal, {differ} differ by > 1e-3 ({shadowed} shadowed), mean |dV| {mean:.2e}, worst {worst:.3}", geometry.len());
        assert!(shadowed > 20, "{label}: only {shadowed} shadowed pixels");
        assert!(
            mean < 2e-3,
            "{label}: mean |dV| {mean:.2e} between the rasters"
        );
        assert!(
            (differ as f64) < 0.02 * geometry.len() as f64,
            "{label}: {differ} of {} pixels differ by > 1e-3",
            geometry.len()
        );
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} cases compared");
}

/// The documented paths: `--set raster=compute|auto` in `render` and `compare`, what run.json,
/// results.jsonl/.csv and the report say of it, and a bad value refused with nothing written.
#[test]
fn the_raster_setting_is_recorded_and_checked() {
    let dir = common::temp_dir("raster_setting");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, common::random_scene_toml(3, 48, 128)).unwrap();
    let scene = scene.to_str().unwrap();
    for raster in ["hardware", "compute", "auto"] {
        let out = dir.join(format!("render-{raster}"));
        common::ok(
            common::penumbra(&[
                "render",
                "--scene",
                scene,
                "--method",
                "regular:n=3",
                "--set",
                &format!("raster={raster}"),
                "--out",
                out.to_str().unwrap(),
            ]),
            "render",
        );
        let run: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("run.json")).unwrap()).unwrap();
        assert_eq!(run["raster"]["setting"], raster, "{}", run["raster"]);
        assert_eq!(run["render"]["raster"], raster);
        match raster {
            "auto" => {
                let auto = &run["raster"]["auto"];
                let (hw, cs) = (
                    auto["hardware_ms"].as_f64().unwrap(),
                    auto["compute_ms"].as_f64().unwrap(),
                );
                assert!(
                    hw > 0.0 && cs > 0.0 && auto["maps"] == 8 && auto["map_size"] == 128,
                    "{auto}"
                );
                // auto keeps whichever raster it timed faster.
                assert_eq!(
                    run["raster"]["used"],
                    if cs < hw { "compute" } else { "hardware" },
                    "{auto}"
                );
            }
            _ => {
                assert_eq!(run["raster"]["used"], raster);
                assert!(run["raster"]["auto"].is_null());
            }
        }
    }
    let out = dir.join("compare");
    common::ok(
        common::penumbra(&[
            "compare",
            "--scene",
            scene,
            "--methods",
            "hard,regular:n=3",
            "--repeats",
            "1",
            "--samples",
            "8",
            "--set",
            "raster=compute",
            "--out",
            out.to_str().unwrap(),
        ]),
        "compare",
    );
    let rows = common::rows(&out);
    assert_eq!(rows.len(), 2);
    assert!(rows.iter().all(|r| r["raster"] == "compute"), "{rows:?}");
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    // The raster column follows the reference (the adapter's quoted name holds commas).
    assert!(
        csv.lines().next().unwrap().contains(",reference,raster,"),
        "{csv}"
    );
    assert!(
        csv.lines()
            .skip(1)
            .all(|l| l.contains(",continuous 8x8,compute,")),
        "{csv}"
    );
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("| shadow-map raster | compute |"), "{md}");

    let bad = dir.join("bad");
    let run = common::penumbra(&[
        "render",
        "--scene",
        scene,
        "--set",
        "raster=gpu",
        "--out",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(1));
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        err.contains("--set raster=gpu") && err.contains("`hardware`, `compute`, `auto`"),
        "{err}"
    );
    assert!(!bad.exists(), "nothing written");
}

/// The GPU-steered loop over compute maps: no wait in frame mode, V bit-identical to the waiting
/// loop's and to the fixed-function raster's, the same maps, and the record says only the
/// requested maps were rasterized.
#[test]
fn the_steered_frame_over_compute_maps_equals_the_waiting_loop() {
    let ctx = common::gpu();
    let dir = common::temp_dir("raster_steered");
    let options = FrameOptions {
        mode: TimingMode::Frame,
        pictures: false,
    };
    for (spec, seed) in [
        ("adaptive", 11),
        ("adaptive:p_m=0", 5),
        ("adaptive:max_level=3", 9),
        ("adaptive:preset=balanced", 13),
    ] {
        let text = common::random_scene_toml(seed, 64, 128);
        let run = |raster: &str, steer: &str| {
            let method = Method::parse(
                &format!("{spec},steer={steer}").replace("adaptive,", "adaptive:"),
                &[],
            )
            .unwrap();
            let s = scene(&text, &dir, raster, &[]);
            let mut r = Renderer::new(ctx, &s, &method).unwrap();
            r.frame(options).unwrap()
        };
        let steered = run("compute", "gpu");
        let waiting = run("compute", "cpu");
        let fixed = run("hardware", "gpu");
        assert_eq!(
            steered.output.syncs, 0,
            "{spec}: the steered frame reads nothing back"
        );
        assert!(
            waiting.output.syncs > 0,
            "{spec}: the waiting loop reads back each level"
        );
        assert_eq!(
            steered.output.shadow_maps, waiting.output.shadow_maps,
            "{spec}: maps"
        );
        assert!(
            steered.output.shadow_maps > 9,
            "{spec}: {} maps, the loop refined",
            steered.output.shadow_maps
        );
        assert_eq!(
            steered.output.record["steer_raster"]
                .as_str()
                .unwrap()
                .split(':')
                .next(),
            Some("compute"),
            "{spec}"
        );
        for (other, name) in [
            (&waiting, "the waiting loop"),
            (&fixed, "the fixed-function raster"),
        ] {
            let differ = steered
                .visibility
                .iter()
                .zip(&other.visibility)
                .filter(|(a, b)| a != b)
                .count();
            assert_eq!(
                differ, 0,
                "{spec}: V differs from {name} at {differ} pixels"
            );
        }
        println!(
            "{spec}: {} maps, V equal to the waiting loop's and the hardware raster's",
            steered.output.shadow_maps
        );
    }
}

/// Map storage stays inside `shadow_map_budget_mib` under the compute raster: its chain takes a
/// quarter of the budget (at most 32 maps) and the method's arrays the rest; a budget of one map
/// is refused with one line naming the setting.
#[test]
fn compute_maps_stay_inside_the_budget() {
    use penumbra::research::scene::CullMode;
    use penumbra::research::stages::raster::{chain_maps, Raster};
    let ctx = common::gpu();
    let (hardware, compute) = (
        Raster::new(ctx, CullMode::Back, false, 4).unwrap(),
        Raster::new(ctx, CullMode::Back, true, 4).unwrap(),
    );
    // 256² maps are 256 KiB: 4 MiB holds 16, of which the chain takes 4.
    assert_eq!(hardware.maps_per_array(ctx, 256, 4).unwrap(), 16);
    assert_eq!(chain_maps(ctx, 256, 4).unwrap(), 4);
    assert_eq!(compute.maps_per_array(ctx, 256, 4).unwrap(), 12);
    // 512 MiB of 512² maps: 512 in all, a chain of 32 (not a quarter: the cap), 480 for the arrays.
    assert_eq!(chain_maps(ctx, 512, 512).unwrap(), 32);
    assert_eq!(
        compute.maps_per_array(ctx, 512, 512).unwrap(),
        480.min(ctx.limits().max_texture_array_layers)
    );
    let e = compute
        .maps_per_array(ctx, 1024, 4)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("raster = compute needs two 1024x1024 maps")
            && e.contains("shadow_map_budget_mib = 4"),
        "{e}"
    );
    assert!(
        hardware.maps_per_array(ctx, 1024, 4).is_ok(),
        "the fixed-function raster needs one"
    );
}
