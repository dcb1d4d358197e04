//! The sun's cascaded shadow maps (docs/lights.md "Cascades"): the kernel against its twin, the
//! cascade study on `sun-grove-small` (sun-grove's stand-in: the fetched oak is not in CI), and
//! the study's and the method's bad input.

mod common;
use penumbra::research::frame::{frame_uniform, Renderer};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::cascades::{split::Scheme, CascadeBuffers, CascadeMaps};
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;
use penumbra::research::stages::cascades::NO_CASCADE;
use penumbra::research::stages::twin;
use penumbra_lab::reference::truth::Cache;
use penumbra_lab::reference::ReferenceMode;
use penumbra_lab::studies::cascades::{self, CascadeJob};

fn stand_in(extra: &[(&str, &str)]) -> Scene {
    let mut sets = vec![
        ("resolution".to_string(), "128".to_string()),
        ("shadow_map_size".to_string(), "256".to_string()),
    ];
    sets.extend(extra.iter().map(|(k, v)| (k.to_string(), v.to_string())));
    Scene::load("sun-grove-small", &sets).unwrap()
}

#[test]
fn the_kernel_matches_its_twin_on_every_map_and_filter() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let ctx = common::gpu();
    for raster in ["hardware", "compute"] {
        let scene = stand_in(&[("raster", raster)]);
        for filter in ["hard", "pcf"] {
            let method = Method::new(CascadeMaps {
                n: 4,
                split: Scheme::Practical,
                lambda: 0.5,
                filter,
            });
            let mut r = Renderer::new(ctx, &scene, &method).unwrap();
            let f = r.frame(TimingMode::Frame).unwrap();
            let b: CascadeBuffers = r.inspect().unwrap().expect("cascades keeps its buffers");
            let (v, chosen) = twin::cascades::cascades(
                &frame_uniform(&scene),
                &b.filter,
                &b.uniform,
                &b.placement.samples,
                &b.maps,
                &b.disk,
                &f.gbuffer,
            );
            let g = &f.gbuffer;
            let geometry: Vec<usize> = (0..g.position.len())
                .filter(|&i| g.is_geometry(i))
                .collect();
            let differ = (0..chosen.len())
                .filter(|&i| chosen[i] != b.chosen[i])
                .count();
            assert_eq!(
                differ, 0,
                "{raster} {filter}: {differ} pixels took another cascade than the twin's"
            );
            assert!(
                (0..chosen.len()).all(|i| (chosen[i] == NO_CASCADE) != g.is_geometry(i)),
                "{raster} {filter}: background alone has no cascade"
            );
            let used: std::collections::BTreeSet<u32> =
                geometry.iter().map(|&i| b.chosen[i]).collect();
            assert_eq!(used.len(), 4, "{raster} {filter}: cascades used {used:?}");
            let worst = geometry
                .iter()
                .map(|&i| (v[i] - f.visibility[i]).abs())
                .fold(0.0f32, f32::max);
            let shadowed = geometry.iter().filter(|&&i| f.visibility[i] < 1.0).count();
            println!("{raster} {filter}: {} geometry pixels, cascades {used:?}, {shadowed} shadowed, worst |V − twin| {worst:.2e}", geometry.len());
            assert!(
                shadowed > 100,
                "{raster} {filter}: only {shadowed} shadowed pixels"
            );
            assert!(
                worst <= 1e-5,
                "{raster} {filter}: V differs from the twin by {worst}"
            );
            // run.json's figures: the slice ends and each map's texel.
            let rec = &f.output.record;
            assert_eq!(rec["split_depths"].as_array().unwrap().len(), 5, "{rec}");
            assert_eq!(rec["texel_world"].as_array().unwrap().len(), 4, "{rec}");
        }
    }
}

#[test]
fn the_maps_follow_the_camera_by_whole_texels() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let scene = stand_in(&[]);
    let m = CascadeMaps {
        n: 3,
        split: Scheme::Log,
        lambda: 0.5,
        filter: "hard",
    };
    let a = m.place(&scene);
    let mut moved = scene.clone();
    let step = glam::Vec3::new(0.37, 0.0, -0.21);
    moved.camera.eye += step;
    moved.camera.target += step;
    let b = m.place(&moved);
    let mut whole_texels = 0;
    for (k, (sa, sb)) in a.samples.iter().zip(&b.samples).enumerate() {
        assert_eq!(
            sa.texel_angle, sb.texel_angle,
            "cascade {k}: the texel keeps its size"
        );
        // A world point lands at texel coordinates that differ by whole texels between the two maps.
        let size = scene.render.shadow_map_size as f32;
        let to_texel = |s: &penumbra::research::gpu::structs::GpuSample, p: glam::Vec3| {
            let c = glam::Mat4::from_cols_array_2d(&s.light_from_world) * p.extend(1.0);
            glam::Vec2::new(c.x * 0.5 + 0.5, 0.5 - c.y * 0.5) * size
        };
        for p in [
            glam::Vec3::new(3.0, 0.0, 40.0),
            glam::Vec3::new(-20.0, 5.0, 80.0),
        ] {
            let d = to_texel(sa, p) - to_texel(sb, p);
            let off = (d - d.round()).abs().max_element();
            assert!(
                off < 2e-2,
                "cascade {k}: moved by {d} texels, {off} off a whole texel"
            );
            whole_texels += (d.round().abs().max_element() >= 1.0) as u32;
        }
    }
    // The maps did move with the camera (the finer cascades by several texels).
    assert!(
        whole_texels >= 2,
        "only {whole_texels} points moved by a texel or more"
    );
}

#[test]
fn the_study_on_the_stand_in_measures_error_and_density() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let ctx = common::gpu();
    let scene = stand_in(&[]);
    let job = CascadeJob {
        scene: &scene,
        ns: vec![1, 2, 3, 4],
        schemes: Scheme::ALL.to_vec(),
        lambda: 0.5,
        filter: "hard",
        reference: ReferenceMode::DEFAULT_CONTINUOUS,
        cache: Cache::Off,
    };
    let lines = cascades::run(ctx, &job, &|l| println!("{l}")).unwrap();
    assert_eq!(lines.len(), 12);
    for l in &lines {
        let share: f64 = l.cascades.iter().map(|c| c.share).sum();
        assert!(
            (share - 1.0).abs() < 1e-9,
            "{}: shares sum to {share}",
            l.label
        );
        assert_eq!(
            l.cascades.iter().map(|c| c.pixels).sum::<usize>(),
            l.geometry_pixels,
            "{}",
            l.label
        );
        for c in &l.cascades {
            let d = c.density_median;
            println!(
                "{} cascade {}: {:.1}–{:.1}, texel {:.4}, share {:.3}, density {d:?}",
                l.label, c.index, c.near, c.far, c.texel_world, c.share
            );
            assert_eq!(d.is_some(), c.pixels > 0, "{} cascade {}", l.label, c.index);
            assert!(
                d.is_none_or(|d| d.is_finite() && d > 0.0),
                "{} cascade {}: density {d:?}",
                l.label,
                c.index
            );
            assert!(
                c.texel_world > 0.0 && c.far > c.near,
                "{} cascade {}",
                l.label,
                c.index
            );
        }
    }
    let rmse = |split: &str, n: u32| {
        lines
            .iter()
            .find(|l| l.split == split && l.n == n)
            .unwrap()
            .core
            .rmse
    };
    // One cascade is one map whatever the scheme.
    assert_eq!(rmse("uniform", 1), rmse("log", 1));
    for split in ["uniform", "log", "practical"] {
        println!(
            "{split}: RMSE n=1 {:.5}, n=4 {:.5}",
            rmse(split, 1),
            rmse(split, 4)
        );
        assert!(
            rmse(split, 4) < 0.8 * rmse(split, 1),
            "{split}: four cascades do not beat one"
        );
    }
    // The practical split's first cascade is finer than the uniform one's, its texels denser.
    let first = |split: &str| {
        lines
            .iter()
            .find(|l| l.split == split && l.n == 4)
            .unwrap()
            .cascades[0]
            .texel_world
    };
    assert!(first("practical") < first("uniform"));
    let files = cascades::files::files(&lines).unwrap();
    let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "cascades.jsonl",
            "cascades.csv",
            "cascades.md",
            "charts/cascades.png",
            "charts/cascades.svg",
            "report.html"
        ]
    );
    let csv = String::from_utf8(files[1].1.clone()).unwrap();
    assert_eq!(csv.lines().count(), 1 + 3 * (1 + 2 + 3 + 4), "{csv}");
}

#[test]
fn the_command_writes_its_set_and_refuses_bad_flags() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = common::temp_dir("cascades_cmd");
    let out = dir.join("out");
    let small = [
        "--scene",
        "sun-grove-small",
        "--set",
        "resolution=64",
        "--set",
        "shadow_map_size=128",
        "--samples",
        "4",
    ];
    let run = common::ok(
        common::penumbra(
            &[
                &[
                    "cascades",
                    "--n",
                    "1,2",
                    "--split",
                    "log,practical",
                    "--out",
                    out.to_str().unwrap(),
                ][..],
                &small[..],
            ]
            .concat(),
        ),
        "cascades",
    );
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(
        text.contains("| practical (λ = 0.5) |") && text.contains("n = 2"),
        "{text}"
    );
    for f in [
        "cascades.jsonl",
        "cascades.csv",
        "cascades.md",
        "charts/cascades.svg",
        "report.html",
    ] {
        assert!(out.join(f).exists(), "{f} not written");
    }
    assert_eq!(
        std::fs::read_to_string(out.join("cascades.jsonl"))
            .unwrap()
            .lines()
            .count(),
        4
    );
    for (flags, says) in [
        (
            &["--n", "0"][..],
            "--n 0: each number of cascades must be a whole number in 1..=8",
        ),
        (
            &["--n", "9"][..],
            "--n 9: each number of cascades must be a whole number in 1..=8",
        ),
        (&["--n", "2,2"][..], "--n 2: given twice"),
        (
            &["--split", "cubic"][..],
            "--split cubic: use uniform, log or practical",
        ),
        (
            &["--lambda", "1.5"][..],
            "--lambda 1.5: the log split's weight must be a number in 0..=1",
        ),
        (
            &["--lambda", "NaN"][..],
            "--lambda NaN: the log split's weight must be a number in 0..=1",
        ),
        (&["--filter", "box"][..], "--filter box: use hard or pcf"),
    ] {
        let bad = dir.join("bad");
        let r = common::penumbra(
            &[
                &["cascades", "--out", bad.to_str().unwrap()][..],
                &small[..],
                flags,
            ]
            .concat(),
        );
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{flags:?}: {err}");
        assert_eq!(err.trim(), format!("error: {says}"), "{flags:?}");
        assert!(!bad.exists(), "{flags:?}: nothing written");
    }
    // A scene whose light is not a sun: the method's one line, before anything is traced.
    let bad = dir.join("bad");
    let r = common::penumbra(&[
        "cascades",
        "--scene",
        "default",
        "--out",
        bad.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1));
    assert!(err.trim().starts_with("error: cascades: light kind `rect` is not supported yet (cascades are orthographic maps along the sun's direction)"), "{err}");
    assert!(!bad.exists());
    // The method's parameters, in render.
    for (spec, says) in [
        ("cascades:n=0", "cascades: n = 0 is outside 1..=8"),
        (
            "cascades:split=cubic",
            "cascades: parameter split = `cubic`: use one of uniform, log, practical",
        ),
        ("cascades:lambda=2", "cascades: lambda = 2 is outside 0..=1"),
        (
            "cascades:filter=box",
            "cascades: parameter filter = `box`: use one of hard, pcf",
        ),
    ] {
        let r = common::penumbra(&[
            "render",
            "--scene",
            "sun-grove-small",
            "--method",
            spec,
            "--out",
            bad.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{spec}: {err}");
        assert!(
            err.trim().starts_with(&format!("error: {says}")),
            "{spec}: {err}"
        );
        assert!(!bad.exists(), "{spec}: nothing written");
    }
}

/// docs/lights.md's spelled-out defaults are the defaults.
#[test]
fn the_documented_spec_is_the_default() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let spelled =
        Method::parse("cascades:n=4,split=practical,lambda=0.5,filter=hard", &[]).unwrap();
    assert_eq!(spelled, Method::parse("cascades", &[]).unwrap());
    assert_eq!(spelled.label(), "cascades:n=4,split=practical");
    assert_eq!(
        Method::parse("cascades:split=log,filter=pcf", &[])
            .unwrap()
            .label(),
        "cascades:n=4,split=log,filter=pcf"
    );
}
