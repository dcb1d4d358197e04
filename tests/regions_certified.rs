//! `regions` with `certify = on` (docs/regions.md, "Certified classes"): a class whose plan
//! under-counts is caught by its bound and stepped up; the frame is met only where the certified
//! bound is at most T; the frame-wide setting is taken where it is predicted cheaper, and not
//! where the plan is.

mod common;
use penumbra::research::frame::{FrameOptions, FrameResult, Renderer};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;

fn scene(seed: u64) -> Scene {
    Scene::parse(
        &common::random_scene_toml(seed, 128, 256),
        "random",
        None,
        &[],
    )
    .unwrap()
}

fn frame(sc: &Scene, spec: &str) -> FrameResult {
    let method = Method::parse(spec, &[]).unwrap();
    let mut renderer = Renderer::new(common::gpu(), sc, &method).expect("renderer");
    renderer
        .frame(FrameOptions {
            mode: TimingMode::Frame,
            pictures: false,
        })
        .expect("frame")
}

fn certified(r: &FrameResult) -> &serde_json::Value {
    &r.output.record["certified"]
}

#[test]
fn an_under_counting_class_is_caught_and_stepped_up() {
    // The plan decided for 0.3 gives every class too few samples for 0.03.
    let sc = scene(17);
    let spec =
        "regions:target=0.03,plan_target=0.3,filter=none,fallback=off,pixels=128,max_size=512";
    let r = frame(&sc, spec);
    let c = certified(&r);
    let classes = c["classes"].as_array().expect("classes");
    let stepped: Vec<_> = classes
        .iter()
        .filter(|k| k["steps"].as_u64().unwrap() > 0)
        .collect();
    println!("{}", serde_json::to_string_pretty(c).unwrap());
    assert!(!stepped.is_empty(), "no class was stepped up: {classes:?}");
    for k in &stepped {
        let tried = k["tried"].as_array().unwrap();
        let first = tried[0][1].as_f64().unwrap();
        let last = tried[tried.len() - 1][1].as_f64().unwrap();
        // Stepped because its plan's bound was over T; each step until the last was over T.
        assert!(first > 0.03, "stepped from a bound of {first} ≤ T: {k}");
        for t in &tried[..tried.len() - 1] {
            assert!(
                t[1].as_f64().unwrap() > 0.03,
                "stepped past a certified setting: {k}"
            );
        }
        assert!(last < first, "the steps did not lower the bound: {k}");
        assert_eq!(
            k["certified"].as_bool().unwrap(),
            k["bound"].as_f64().unwrap() <= 0.03
        );
    }
    // The plan alone (certify = off) renders fewer maps: the steps are what the bound asked for.
    let plan = frame(
        &sc,
        "regions:target=0.03,plan_target=0.3,certify=off,max_size=512",
    );
    assert!(plan.output.record["certified"].is_null());
    assert!(
        r.output.shadow_maps > plan.output.shadow_maps,
        "certified {} maps, plan {}",
        r.output.shadow_maps,
        plan.output.shadow_maps
    );
    // The trace is its own timing key, inside the frame.
    assert!(c["trace_ms"].as_f64().unwrap() > 0.0);
    assert!(r.total_ms >= c["trace_ms"].as_f64().unwrap());
}

#[test]
fn met_only_where_the_certified_bound_is_at_most_the_target() {
    let sc = scene(5);
    // Out of reach: one sample on 64² maps at the most, 0.002 asked.
    let r = frame(
        &sc,
        "regions:target=0.002,filter=none,max_n=1,min_size=64,max_size=64,pixels=128",
    );
    let c = certified(&r);
    let bound = c["bound"].as_f64().unwrap();
    assert!(bound > 0.002, "bound {bound}");
    assert_eq!(r.output.record["target_met"], false);
    // Each setting a class could end on is bounded at δ/(C·S): here the filter and n = 1 at 64².
    let per_setting = |c: &serde_json::Value, settings: u64| {
        assert_eq!(c["reachable_settings"], settings);
        // δ is shared by the plan's class groups, at least the classes kept (an empty one is
        // dropped after its share is set).
        let classes = c["classes"].as_array().unwrap().len() as f64;
        let groups = 0.05 / (c["delta_per_setting"].as_f64().unwrap() * settings as f64);
        assert!(
            (groups - groups.round()).abs() < 1e-6 && groups.round() >= classes,
            "δ shared by {groups} groups, {classes} classes"
        );
    };
    per_setting(c, 2);
    // Within reach: the same frame at a loose target is met, its bound at most T.
    let r = frame(
        &sc,
        "regions:target=0.25,filter=none,pixels=128,max_size=512",
    );
    let c = certified(&r);
    let bound = c["bound"].as_f64().unwrap();
    assert_eq!(
        r.output.record["target_met"],
        bound <= 0.25,
        "bound {bound}"
    );
    assert_eq!(r.output.record["target_met"], true, "bound {bound}");
    // n of 1, 2, 3, 4, 6, 8, 11, 16 at sides 64, 96, 128, 192, 256, 368, 512, and the filter.
    per_setting(c, 1 + 8 * 7);
    // The frame's bound is the classes' in quadrature, weighted by their pixels.
    let sum: f64 = c["classes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|k| k["share"].as_f64().unwrap() * k["bound"].as_f64().unwrap().powi(2))
        .sum();
    assert!(
        (sum.sqrt() - bound).abs() < 1e-9,
        "{} against {bound}",
        sum.sqrt()
    );
}

#[test]
fn the_frame_wide_setting_is_taken_where_it_is_cheaper() {
    let sc = scene(29);
    // A loose target that the filter meets in every class: the frame is pcss's, bit for bit.
    let r = frame(&sc, "regions:target=0.3,pixels=64,max_size=512");
    let c = certified(&r);
    assert_eq!(c["fallback"]["setting"], "pcss", "{c}");
    assert_eq!(r.output.record["target_met"], true);
    let pcss = frame(&sc, "pcss");
    let differ = r
        .visibility
        .iter()
        .zip(&pcss.visibility)
        .filter(|(a, b)| a.to_bits() != b.to_bits())
        .count();
    assert_eq!(differ, 0, "{differ} pixels differ from pcss's frame");
    // Grids only: with a generous ratio the frame-wide grid is taken, the record says which and
    // why (its predicted cost against the plan's); with fallback = off it is not.
    let spec = "regions:target=0.05,filter=none,pixels=64,max_size=512,merge=off";
    let wide = frame(&sc, &format!("{spec},fallback=100"));
    let f = &certified(&wide)["fallback"];
    assert_eq!(f["taken"], true, "{f}");
    assert!(
        f["setting"].as_str().unwrap().starts_with("regular:n="),
        "{f}"
    );
    assert!(f["frame_wide_cost"].as_f64().unwrap() <= 100.0 * f["plan_cost"].as_f64().unwrap());
    let off = frame(&sc, &format!("{spec},fallback=off"));
    assert_eq!(certified(&off)["fallback"]["taken"], false);
    // Where the plan is predicted cheaper (maps priced at their texels alone, so separate classes
    // cost less than one grid of the top class's samples everywhere) it is kept.
    let plan = frame(&sc, &format!("{spec},fallback=1,map_cost=0"));
    let f = &certified(&plan)["fallback"];
    println!("{f}");
    assert!(
        f["frame_wide_cost"].as_f64().unwrap() > f["plan_cost"].as_f64().unwrap(),
        "{f}"
    );
    assert_eq!(f["taken"], false, "{f}");
}

/// `hold = on` (the default): a frame starts each class from the setting the previous frame
/// ended on. On an unchanged scene the second frame renders the first frame's V from the maps of
/// its final settings alone (no plan, no step-ups), and the third renders the second's; a grid
/// class goes down to the filter only where the frame's bound stays within T / 1.15; `hold = off`
/// decides afresh every frame.
#[test]
fn a_held_frame_starts_from_the_settings_it_ended_on() {
    let sc = scene(17);
    let frames = |spec: &str| -> Vec<FrameResult> {
        let method = Method::parse(spec, &[]).unwrap();
        let mut renderer = Renderer::new(common::gpu(), &sc, &method).expect("renderer");
        (0..3)
            .map(|_| {
                renderer
                    .frame(FrameOptions {
                        mode: TimingMode::Frame,
                        pictures: false,
                    })
                    .expect("frame")
            })
            .collect()
    };
    let settings = |r: &FrameResult| -> Vec<(u64, String)> {
        certified(r)["classes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|k| {
                (
                    k["class"].as_u64().unwrap(),
                    k["setting"].as_str().unwrap().to_string(),
                )
            })
            .collect()
    };
    let steps = |r: &FrameResult| -> u64 {
        certified(r)["classes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|k| k["steps"].as_u64().unwrap())
            .sum()
    };
    let same_v = |a: &FrameResult, b: &FrameResult| -> usize {
        a.visibility
            .iter()
            .zip(&b.visibility)
            .filter(|(x, y)| x.to_bits() != y.to_bits())
            .count()
    };
    let bound = |r: &FrameResult| certified(r)["bound"].as_f64().unwrap();
    // Without the filter: the plan under-counts, frame 1 steps up to meet T, and the later
    // frames start where it ended.
    let spec =
        "regions:target=0.03,plan_target=0.3,filter=none,fallback=off,pixels=128,max_size=512";
    let held = frames(spec);
    assert!(steps(&held[0]) > 0, "the plan was not stepped up");
    assert!(bound(&held[0]) <= 0.03, "bound {}", bound(&held[0]));
    assert_eq!(certified(&held[0])["held"], false);
    for (k, r) in held.iter().enumerate().skip(1) {
        assert_eq!(certified(r)["held"], true, "frame {k}");
        assert_eq!(steps(r), 0, "frame {k} stepped up again");
        assert_eq!(settings(r), settings(&held[0]), "frame {k}'s settings");
        assert_eq!(
            same_v(r, &held[0]),
            0,
            "frame {k}'s V differs from frame 1's"
        );
        assert_eq!(bound(r), bound(&held[0]));
    }
    assert!(
        held[1].output.shadow_maps < held[0].output.shadow_maps,
        "held frame {} maps, first {}",
        held[1].output.shadow_maps,
        held[0].output.shadow_maps
    );
    assert_eq!(held[2].output.shadow_maps, held[1].output.shadow_maps);
    // hold = off: every frame decides afresh, with the first frame's maps.
    let fresh = frames(&format!("{spec},hold=off"));
    for r in &fresh[1..] {
        assert_eq!(certified(r)["held"], false);
        assert_eq!(r.output.shadow_maps, fresh[0].output.shadow_maps);
        assert_eq!(same_v(r, &fresh[0]), 0);
    }
    // With the filter: a class the second frame moves down to it leaves the frame within
    // T / 1.15, and the third frame holds the second's settings and V.
    let with_filter = frames("regions:target=0.03,plan_target=0.3,pixels=128,max_size=512");
    let (first, second) = (settings(&with_filter[0]), settings(&with_filter[1]));
    let down = first
        .iter()
        .zip(&second)
        .filter(|(a, b)| a.1 != "pcss" && b.1 == "pcss")
        .count();
    println!("with the filter: {first:?} then {second:?}, {down} down");
    if down > 0 {
        assert!(
            bound(&with_filter[1]) <= 0.03 / 1.15,
            "{}",
            bound(&with_filter[1])
        );
    }
    assert!(bound(&with_filter[1]) <= 0.03);
    assert_eq!(settings(&with_filter[2]), second);
    assert_eq!(same_v(&with_filter[2], &with_filter[1]), 0);
}

#[test]
fn a_paired_truth_traces_two_estimates_of_fewer_rays_and_bounds_alike() {
    // The plan under-counts (decided for 0.3), so its classes have error to measure; no filter,
    // no fallback: every class's first bound is the plan's, whose V does not depend on the truth.
    let sc = scene(17);
    let base =
        "regions:target=0.03,plan_target=0.3,filter=none,fallback=off,pixels=256,max_size=512";
    let full = frame(&sc, base);
    let paired = frame(&sc, &format!("{base},truth_side=4"));
    let (f, p) = (certified(&full), certified(&paired));
    // The same pixels, each traced twice at 4 × 4 instead of once at 32 × 32.
    assert_eq!(f["traced_pixels"], p["traced_pixels"]);
    let (rf, rp) = (f["rays"].as_u64().unwrap(), p["rays"].as_u64().unwrap());
    assert!(rf > 0);
    // A sample whose light point the receiver faces away from casts no ray, so the counts are
    // per traced pixel at most 1,024 and 2 × 16, and in the same proportion within 1%.
    let traced = f["traced_pixels"].as_u64().unwrap();
    assert!(rf <= traced * 1024 && rp <= traced * 2 * 16);
    let per_pixel = (rf as f64 / 1024.0, rp as f64 / 32.0);
    assert!(
        (per_pixel.0 / per_pixel.1 - 1.0).abs() < 0.01,
        "rays: full {rf}, paired {rp}"
    );
    // The plan's bound per class, measured on the same draws with either truth: the pair's
    // noise widens it a little and moves it either way, never far.
    let firsts = |c: &serde_json::Value| -> Vec<f64> {
        c["classes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|k| k["tried"][0][1].as_f64().unwrap())
            .collect()
    };
    let (bf, bp) = (firsts(f), firsts(p));
    println!("plan's bounds: full {bf:?}, paired {bp:?}");
    assert_eq!(bf.len(), bp.len());
    for (a, b) in bf.iter().zip(&bp) {
        assert!(b / a > 0.7 && b / a < 1.5, "full {a}, paired {b}");
    }
    // The frame is met exactly where its paired bound is at most T.
    let bound = p["bound"].as_f64().unwrap();
    assert_eq!(
        paired.output.record["target_met"],
        bound <= 0.03,
        "bound {bound}"
    );
}
