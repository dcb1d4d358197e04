//! The invariants of method.md §3 and the project's extensions, on small scenes.

mod common;
use penumbra::research::frame::{self, FrameResult};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::{AdaptiveParams, Criterion, Layout, Method, Scope, Weights};
use penumbra::research::scene::Scene;

fn small(name: &str, extra: &[(&str, &str)]) -> Scene {
    let mut sets = vec![
        ("resolution".to_string(), "128".to_string()),
        ("shadow_map_size".to_string(), "256".to_string()),
    ];
    sets.extend(extra.iter().map(|(k, v)| (k.to_string(), v.to_string())));
    Scene::load(name, &sets).unwrap()
}

fn run(scene: &Scene, method: &Method) -> FrameResult {
    frame::render(common::gpu(), scene, method, TimingMode::Frame).unwrap()
}

fn adaptive(p: AdaptiveParams) -> Method {
    Method::adaptive(p)
}

fn rmse(a: &FrameResult, b: &FrameResult) -> f64 {
    let (mut s, mut n) = (0.0f64, 0usize);
    for i in 0..a.visibility.len() {
        if a.gbuffer.is_geometry(i) {
            let d = (a.visibility[i] - b.visibility[i]) as f64;
            s += d * d;
            n += 1;
        }
    }
    (s / n as f64).sqrt()
}

fn assert_valid(r: &FrameResult, what: &str) {
    assert!(
        r.visibility
            .iter()
            .all(|v| v.is_finite() && (0.0..=1.0).contains(v)),
        "{what}: V outside [0,1] or NaN"
    );
}

const UNOCCLUDED: &str = r#"
[camera]
eye = [0.0, 8.0, 10.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 50.0
[light]
center = [1.0, 9.0, -1.0]
edge_u = [3.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 3.0]
[render]
width = 96
height = 96
shadow_map_size = 256
[[mesh]]
builtin = "plane"
scale = 12.0
"#;

#[test]
fn p_m_infinite_renders_exactly_four_maps() {
    let r = run(
        &small("default", &[]),
        &adaptive(AdaptiveParams {
            criterion: Criterion::Pixels {
                p_m: f64::INFINITY,
                growth: 1.0,
            },
            ..Default::default()
        }),
    );
    assert_eq!(r.output.shadow_maps, 4);
    assert_valid(&r, "p_m = inf");
}

#[test]
fn unoccluded_scene_needs_four_maps_and_flags_nothing() {
    let ctx = common::gpu();
    let scene = Scene::parse(UNOCCLUDED, "unoccluded", None, &[]).unwrap();
    for scope in [Scope::Global, Scope::Local] {
        let (r, t) = common::traced(
            ctx,
            &scene,
            &AdaptiveParams {
                scope,
                ..Default::default()
            },
            false,
        );
        assert_eq!(r.output.shadow_maps, 4, "{scope:?}");
        let flagged: u32 = t.levels.iter().flat_map(|l| &l.low_quality).sum();
        assert_eq!(
            flagged, 0,
            "{scope:?}: low-quality pixels in an unoccluded scene"
        );
        let geometry = r.gbuffer.geometry_count();
        let lit = (0..r.visibility.len())
            .filter(|&i| r.gbuffer.is_geometry(i) && r.visibility[i] == 1.0)
            .count();
        assert_eq!(
            lit, geometry,
            "{scope:?}: every geometry pixel must be fully lit"
        );
    }
}

#[test]
fn always_split_equals_the_regular_17_grid() {
    let scene = small("default", &[]);
    let reg = run(&scene, &Method::regular(17));
    {
        let scope = Scope::Global;
        let a = run(
            &scene,
            &adaptive(AdaptiveParams {
                criterion: Criterion::Pixels {
                    p_m: -1.0,
                    growth: 1.0,
                },
                scope,
                ..Default::default()
            }),
        );
        assert_eq!(a.output.shadow_maps, 289);
        let worst = a
            .visibility
            .iter()
            .zip(&reg.visibility)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f32, f32::max);
        println!("always split vs regular 17: max |dV| = {worst:e}");
        assert!(worst <= 1e-6, "max |V_adaptive - V_regular| = {worst}");
    }
    // scope = local with every quad split is the regular grid's trapezoid-free box rule per pixel:
    // it must use all 289 maps too.
    let l = run(
        &scene,
        &adaptive(AdaptiveParams {
            criterion: Criterion::Pixels {
                p_m: -1.0,
                growth: 1.0,
            },
            scope: Scope::Local,
            ..Default::default()
        }),
    );
    assert_eq!(l.output.shadow_maps, 289);
}

#[test]
fn centred_layout_fully_split_is_the_centred_regular_grid() {
    // The inset lattice's points at max_level L are the cell centres of the (2^L+1)² grid, and the
    // border strips make every weight equal (docs/method.md §7.1): same maps, same V.
    let ctx = common::gpu();
    let scene = small("default", &[]);
    for (max_level, n) in [(1u32, 3u32), (2, 5)] {
        let reg = run(
            &scene,
            &Method::parse(&format!("regular:n={n},layout=centred"), &[]).unwrap(),
        );
        for weights in [Weights::Area, Weights::Coons] {
            let p = AdaptiveParams {
                criterion: Criterion::Pixels {
                    p_m: -1.0,
                    growth: 1.0,
                },
                max_level,
                weights,
                layout: Layout::Centred,
                ..Default::default()
            };
            let (a, t) = common::traced(ctx, &scene, &p, false);
            assert_eq!(a.output.shadow_maps, n * n, "L {max_level} {weights:?}");
            let w0 = t.weights[t.rendered[0] as usize];
            assert!(
                t.rendered.iter().all(|&k| t.weights[k as usize] == w0),
                "L {max_level} {weights:?}: unequal weights {:?}",
                t.weights
            );
            assert_eq!(w0, 1.0 / (n * n) as f32);
            let worst = a
                .visibility
                .iter()
                .zip(&reg.visibility)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0f32, f32::max);
            assert!(
                worst <= 1e-6,
                "L {max_level} {weights:?}: max |V_adaptive - V_centred {n}x{n}| = {worst}"
            );
        }
    }
    // Partly split: the weights still sum to one and every rendered sample carries weight.
    let p = AdaptiveParams {
        criterion: Criterion::Pixels {
            p_m: 20.0,
            growth: 1.0,
        },
        max_level: 3,
        weights: Weights::Coons,
        layout: Layout::Centred,
        ..Default::default()
    };
    let (r, t) = common::traced(ctx, &scene, &p, false);
    assert!(
        t.rendered.len() < 81,
        "p_m 20 split everything ({} maps)",
        t.rendered.len()
    );
    let sum: f64 = t.weights.iter().map(|&w| w as f64).sum();
    assert!((sum - 1.0).abs() < 1e-6, "centred partial: Σŵ = {sum}");
    assert_eq!(
        t.weights.iter().filter(|&&w| w > 0.0).count(),
        t.rendered.len()
    );
    assert_valid(&r, "centred partial");
}

#[test]
fn centred_layout_rejects_what_it_cannot_weigh() {
    for spec in [
        "adaptive:layout=centred,scope=local",
        "adaptive:layout=centred",
        "adaptive:layout=jittered",
        "adaptive:layout=grid",
    ] {
        let e = Method::parse(spec, &[])
            .err()
            .unwrap_or_else(|| panic!("{spec} was accepted"))
            .to_string();
        assert!(e.contains("layout"), "{spec}: {e}");
    }
    assert!(Method::parse("adaptive:layout=centred,weights=coons", &[]).is_ok());
}

#[test]
fn weights_sum_to_one_and_visibility_stays_in_range() {
    let ctx = common::gpu();
    let scene = small("default", &[]);
    for weights in [Weights::Level, Weights::Area, Weights::Coons] {
        for p_m in [0.0, 20.0] {
            let p = AdaptiveParams {
                criterion: Criterion::Pixels { p_m, growth: 1.0 },
                weights,
                ..Default::default()
            };
            let (r, t) = common::traced(ctx, &scene, &p, false);
            let sum: f64 = t.weights.iter().map(|&w| w as f64).sum();
            assert!(
                (sum - 1.0).abs() < 1e-6,
                "{weights:?} p_m {p_m}: Σŵ = {sum}"
            );
            let nonzero = t.weights.iter().filter(|&&w| w > 0.0).count();
            assert_eq!(
                nonzero,
                t.rendered.len(),
                "every rendered sample and only those carry weight"
            );
            assert_valid(&r, "global");
        }
    }
    let r = run(
        &scene,
        &adaptive(AdaptiveParams {
            scope: Scope::Local,
            ..Default::default()
        }),
    );
    assert_valid(&r, "local");
}

#[test]
fn default_scene_uses_fewer_maps_and_stays_close_to_regular_17() {
    // The seed's settings (512x512 screen, 512² maps): the criterion counts pixels, so it depends on resolution.
    let scene = Scene::load("default", &[]).unwrap();
    let reg = run(&scene, &Method::regular(17));
    let a = run(&scene, &adaptive(AdaptiveParams::default()));
    let l = run(
        &scene,
        &adaptive(AdaptiveParams {
            scope: Scope::Local,
            ..Default::default()
        }),
    );
    let (ea, el) = (rmse(&a, &reg), rmse(&l, &reg));
    println!(
        "default 512x512, 512² maps: adaptive {} maps RMSE {ea:.5}; local {} maps RMSE {el:.5}; regular 289 maps",
        a.output.shadow_maps, l.output.shadow_maps
    );
    assert!(
        a.output.shadow_maps < 289,
        "adaptive used {} maps",
        a.output.shadow_maps
    );
    assert!(ea < 0.01, "adaptive vs regular 17 RMSE {ea}");
    // scope = local converges to the trapezoid rule over the lattice, not to the 289-point mean, so
    // regular 17 is not its yardstick (the continuous reference is); it must still stay close.
    assert!(el < 0.02, "local vs regular 17 RMSE {el}");
    assert!(
        a.output.syncs <= 5 && l.output.syncs <= 5,
        "syncs {} / {}",
        a.output.syncs,
        l.output.syncs
    );
}

#[test]
fn max_level_bounds_the_lattice() {
    for (max_level, maps) in [(0u32, 4u32), (1, 9), (2, 25)] {
        let r = run(
            &small("default", &[]),
            &adaptive(AdaptiveParams {
                criterion: Criterion::Pixels {
                    p_m: -1.0,
                    growth: 1.0,
                },
                max_level,
                ..Default::default()
            }),
        );
        assert_eq!(r.output.shadow_maps, maps, "max_level {max_level}");
        assert!(r.output.syncs <= max_level + 1);
    }
}

#[test]
fn maps_beyond_the_memory_budget_are_processed_in_chunks_with_the_same_result() {
    // 256² maps are 0.25 MiB: a 2 MiB budget holds 8 maps per array.
    let full = small("default", &[]);
    let tight = small("default", &[("shadow_map_budget_mib", "2")]);
    for method in [
        Method::regular(17),
        adaptive(AdaptiveParams {
            criterion: Criterion::Pixels {
                p_m: -1.0,
                growth: 1.0,
            },
            ..Default::default()
        }),
        adaptive(AdaptiveParams::default()),
    ] {
        let a = run(&full, &method);
        let b = run(&tight, &method);
        assert_eq!(a.output.shadow_maps, b.output.shadow_maps);
        assert_eq!(
            a.visibility, b.visibility,
            "{method:?}: chunked result differs"
        );
        if method.name() == "regular" {
            assert_eq!(b.output.record["maps_per_chunk"], 8);
            assert_eq!(b.output.record["chunks"], 37);
        }
    }
}

#[test]
fn scissor_changes_no_pixel() {
    let scene = small("default", &[]);
    let off = run(
        &scene,
        &adaptive(AdaptiveParams {
            scope: Scope::Local,
            ..Default::default()
        }),
    );
    let on = run(
        &scene,
        &adaptive(AdaptiveParams {
            scope: Scope::Local,
            scissor: true,
            ..Default::default()
        }),
    );
    assert_eq!(off.visibility, on.visibility);
    assert_eq!(off.output.shadow_maps, on.output.shadow_maps);
}

#[test]
fn item_overflow_is_reported_not_clipped() {
    let dir = common::temp_dir("item-overflow").join("out");
    // Growth off: the list stays at 100 items (tests/item_growth.rs shows it growing).
    let out = common::penumbra(&[
        "render",
        "--scene",
        "default",
        "--method",
        "adaptive:scope=local,items=100,items_grow=off",
        "--set",
        "resolution=64",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let e = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{e}");
    assert_eq!(e, "error: overflow: adaptive level 0: the (pixel, quad) item list exceeded its capacity (flags 0x2); the run is not valid\n");
    assert!(!dir.join("run.json").exists());
}

#[test]
fn gpu_timestamps_cover_every_stage_when_enabled() {
    // On CPU adapters the figures are not trustworthy (run.json reports null); this checks the mechanics.
    let ctx = common::gpu();
    let scene = small("default", &[]);
    let method = adaptive(AdaptiveParams::default());
    let mut renderer = frame::Renderer::new(ctx, &scene, &method).unwrap();
    renderer.force_gpu_timestamps();
    let r = renderer.frame(TimingMode::Frame).unwrap();
    let gpu = r.gpu_stages_ms.expect("timestamps recorded when forced");
    for stage in [
        "gbuffer",
        "shadow_raster",
        "shadow_test",
        "reproject_count",
        "neighbourhood",
        "quad_count",
        "subdivide",
        "shade",
    ] {
        let ms = gpu.get(stage).copied();
        assert!(
            ms.is_some_and(|v| v.is_finite() && v >= 0.0),
            "{stage}: {ms:?} in {gpu:?}"
        );
    }
}

/// pole-between-corners plus a box whose penumbra splits the root quad: under the pole, all four
/// root corners see every ground pixel lit (c = 4), so before the probe stage scope = local added the
/// uniform share V = 1 there although the new centre sample, rendered for the box, is blocked.
const POLE_AND_BOX: &str = r#"
[camera]
eye = [6.0, 9.0, 7.0]
target = [0.0, 0.0, 0.5]
fov_y_deg = 50.0
[light]
center = [0.0, 4.0, 0.0]
edge_u = [4.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 4.0]
[render]
width = 96
height = 96
shadow_map_size = 256
[[mesh]]
builtin = "plane"
scale = [2.2, 1.0, 12.0]
[[mesh]]
builtin = "plane"
translate = [0.0, 2.0, 0.0]
scale = [0.8, 1.0, 3.0]
[[mesh]]
builtin = "box"
translate = [0.0, 0.4, 4.0]
scale = [1.5, 0.8, 0.6]
"#;

#[test]
fn local_scope_finds_a_shadow_between_the_corners_of_a_split_quad() {
    let ctx = common::gpu();
    let scene = Scene::parse(POLE_AND_BOX, "pole-and-box", None, &[]).unwrap();
    let reg = run(&scene, &Method::regular(17));
    let p = AdaptiveParams {
        scope: Scope::Local,
        ..Default::default()
    };
    let (local, trace) = common::traced(ctx, &scene, &p, false);
    assert!(
        trace.levels[0].split_base[0] != u32::MAX,
        "the box must split the root quad"
    );
    // Pixels the root's corners see lit (comparison byte 5: c = 4) that the lattice finds shadowed.
    let root = trace.levels[0]
        .counts
        .as_ref()
        .expect("level-0 comparison map read back");
    let between: Vec<usize> = (0..reg.visibility.len())
        .filter(|&i| {
            reg.gbuffer.is_geometry(i)
                && (root[i / 4] >> ((i % 4) * 8)) & 0xff == 5
                && reg.visibility[i] < 0.9
        })
        .collect();
    let mean = |r: &FrameResult| {
        between.iter().map(|&i| r.visibility[i] as f64).sum::<f64>() / between.len() as f64
    };
    let (v_local, v_reg) = (mean(&local), mean(&reg));
    println!("{} pixels hidden between the root corners: mean V local {v_local:.3}, regular 17x17 {v_reg:.3}; probes per level {:?}",
        between.len(), trace.levels.iter().map(|l| l.probes).collect::<Vec<_>>());
    assert!(
        between.len() >= 100,
        "the pole's shadow must lie between the root corners: {} pixels",
        between.len()
    );
    // Without the probe these pixels read V = 1 (the root's uniform share). Local scope integrates
    // with area (trapezoid) weights, the lattice mean does not, hence the tolerance.
    assert!(
        v_local < 0.85 && (v_local - v_reg).abs() < 0.1,
        "local mean V {v_local:.3} under the pole, regular {v_reg:.3}"
    );
}

/// run.json of a stages-mode frame: the steered loop has no sync (only timing waits), the frame
/// splits into raster, decision, shade and waits within its total, and every map drew the whole
/// mesh (no culling under global scope).
#[test]
fn stages_frame_splits_and_the_steered_loop_only_waits_to_time() {
    let ctx = common::gpu();
    let scene = small("default", &[]);
    let method = adaptive(AdaptiveParams {
        steer_cpu: false,
        ..Default::default()
    });
    let r = frame::render(ctx, &scene, &method, TimingMode::Stages).unwrap();
    assert_eq!(r.output.syncs, 0);
    assert!(
        r.timing_waits > 10,
        "stages mode waits per stage: {}",
        r.timing_waits
    );
    let rec = penumbra_lab::record::run_files::run_record(&scene, &method, &r, &ctx.summary, false);
    let split = rec["frame_split_ms"].as_object().expect("frame_split_ms");
    let parts: Vec<&str> = split.keys().map(String::as_str).collect();
    assert_eq!(parts, ["decision", "raster", "shade", "waits"]);
    for part in ["decision", "raster", "shade"] {
        assert!(split[part].as_f64().unwrap() > 0.0, "{part}: {split:?}");
    }
    let sum: f64 = split.values().map(|v| v.as_f64().unwrap()).sum();
    assert!(
        sum <= r.total_ms + 1.0,
        "split {sum} ms over the frame's {} ms",
        r.total_ms
    );
    assert_eq!(
        rec["method_record"]["triangles_per_map_mean"].as_f64(),
        Some(scene.triangle_count() as f64)
    );
    assert_eq!(rec["method_record"]["syncs"], 0);
    assert_eq!(rec["timing"], "stages");
    assert!(
        rec["decision_share"].as_f64().unwrap() > 0.0,
        "{}",
        rec["decision_share"]
    );
    // A frame-mode frame times only its waits: no split or share is claimed from them.
    let f = frame::render(ctx, &scene, &method, TimingMode::Frame).unwrap();
    let rec = penumbra_lab::record::run_files::run_record(&scene, &method, &f, &ctx.summary, false);
    assert_eq!(rec["timing"], "frame");
    for key in ["frame_split_ms", "decision_stages_ms", "decision_share"] {
        assert!(
            rec[key].is_null(),
            "{key} of a frame-mode frame: {}",
            rec[key]
        );
    }
    assert_eq!(f.visibility, r.visibility, "the timing mode changed V");
}
