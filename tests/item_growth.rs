//! scope = local's (pixel, quad) item list follows the need (robustness.md, "Item list growth"):
//! on scenes/slat-roof.toml, a periodic occluder whose penumbrae never end, the default list
//! overflows at level 2; the frame runs again on a grown list, and V is the V of a list large
//! enough from the start, bit for bit.

mod common;
use common::{ok, penumbra, temp_dir};
use penumbra::frame::Renderer;
use penumbra::gpu::timing::TimingMode;
use penumbra::methods::Method;
use penumbra::scene::Scene;

fn run_json(dir: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("run.json")).unwrap()).unwrap()
}

/// 128² holds 16,384 pixels: the default list holds 32 per pixel, 524,288 items.
const DEFAULT_128: u64 = 128 * 128 * 32;

#[test]
fn the_slat_roof_overflows_a_fixed_list_and_completes_on_a_growing_one() {
    let dir = temp_dir("slat-roof-fixed").join("out");
    let d = dir.to_str().unwrap();
    // The held-out failure, reproduced: the default capacity with growth off.
    let out = penumbra(&["render", "--scene", "slat-roof", "--method", "adaptive:scope=local,items_grow=off", "--warm-up", "0", "--out", d]);
    let e = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{e}");
    assert_eq!(e, "error: overflow: adaptive level 2: the (pixel, quad) item list exceeded its capacity (flags 0x2); the run is not valid\n");
    assert!(!dir.exists(), "a failed run writes nothing");

    // Levels 3 and 4 at 128² and 512², growth on (the default): every run completes.
    for (res, method, levels) in [
        ("128", "adaptive:preset=seed,scope=local", 5),
        ("128", "adaptive:scope=local,max_level=3", 4),
        ("512", "adaptive:scope=local,max_level=3", 4),
        ("512", "adaptive:preset=seed,scope=local", 4),
    ] {
        ok(penumbra(&["render", "--scene", "slat-roof", "--method", method, "--set", &format!("resolution={res}"), "--warm-up", "0", "--timing", "frame", "--out", d]), method);
        let r = run_json(&dir);
        let m = &r["method_record"];
        let items = &m["items"];
        let evaluated: Vec<u64> = m["levels"].as_array().unwrap().iter().map(|l| l["pixels_evaluated"].as_u64().unwrap()).collect();
        println!("{res}² {method}: items {items}, per level {evaluated:?}, syncs {}", r["syncs"]);
        assert_eq!(evaluated.len(), levels, "{res}² {method}");
        let capacity = items["capacity"].as_u64().unwrap();
        assert!(evaluated.iter().all(|&n| n <= capacity), "{res}² {method}: {evaluated:?} within {capacity}");
        let again = items["frames_run_again"].as_u64().unwrap();
        if res == "128" {
            // Level 3 alone needs more than the default list: the frame grew it and ran again.
            assert!(evaluated[3] > DEFAULT_128, "{evaluated:?}");
            assert!(again >= 1 && capacity > DEFAULT_128, "{items}");
            // Each run that overflowed read back at least one level: counted, not hidden.
            assert!(r["syncs"].as_u64().unwrap() > levels as u64, "{}", r["syncs"]);
        } else {
            assert_eq!((again, r["syncs"].as_u64()), (0, Some(levels as u64)), "{res}² {method}");
        }
    }
}

/// V's bits from one frame of `spec` on slat-roof at 128² (renderer reused: `frames` frames), with
/// the method record and syncs of each frame.
fn frames(spec: &str, frames: usize) -> Vec<(Vec<u32>, serde_json::Value, u32)> {
    let scene = Scene::load("slat-roof", &[]).unwrap();
    let method = Method::parse(spec, &[]).unwrap();
    let mut r = Renderer::new(common::gpu(), &scene, &method).unwrap();
    (0..frames)
        .map(|_| {
            let f = r.frame(TimingMode::Frame).unwrap();
            (f.visibility.iter().map(|v| v.to_bits()).collect(), f.output.record, f.output.syncs)
        })
        .collect()
}

#[test]
fn a_grown_list_gives_the_v_of_a_list_that_fitted_bit_for_bit() {
    // 4M items hold every level of the seed setting (2.4M at level 4): nothing grows.
    let (fits, rec, syncs) = frames("adaptive:preset=seed,scope=local,items=4000000", 1).remove(0);
    assert_eq!(rec["items"], serde_json::json!({ "capacity": 4_000_000, "frames_run_again": 0, "grown_to": [] }));
    assert_eq!(syncs, 5);
    for spec in ["adaptive:preset=seed,scope=local", "adaptive:preset=seed,scope=local,items=5000", "adaptive:preset=seed,scope=local,items=5000,steer=gpu"] {
        let runs = frames(spec, 2);
        let (v, rec, syncs) = &runs[0];
        let items = &rec["items"];
        let grown: Vec<u64> = items["grown_to"].as_array().unwrap().iter().map(|c| c.as_u64().unwrap()).collect();
        println!("{spec}: {items}, syncs {syncs}");
        assert!(v == &fits, "{spec}: V differs from the run that fitted");
        assert!(!grown.is_empty() && grown.windows(2).all(|w| w[0] < w[1]), "{spec}: {items}");
        assert_eq!(items["capacity"].as_u64(), grown.last().copied());
        assert_eq!(items["frames_run_again"].as_u64(), Some(grown.len() as u64));
        // The runs that overflowed count their read-backs: the waiting loop's levels, or the
        // steered frame's V and records (2 each).
        let again = grown.len() as u32;
        if spec.contains("steer=gpu") {
            assert_eq!(*syncs, 2 * again, "{spec}");
        } else {
            assert!(*syncs >= 5 + again, "{spec}: {syncs}");
        }
        assert_eq!(rec["syncs"].as_u64(), Some(*syncs as u64));
        // The renderer keeps the grown list: its next frame runs once, with the frame's own syncs.
        let (v2, rec2, syncs2) = &runs[1];
        assert!(v2 == &fits, "{spec}: second frame's V");
        assert_eq!((rec2["items"]["frames_run_again"].as_u64(), rec2["items"]["capacity"].as_u64()), (Some(0), grown.last().copied()));
        assert_eq!(*syncs2, if spec.contains("steer=gpu") { 0 } else { 5 });
    }
}

#[test]
fn growth_settings_refuse_bad_values_in_one_line() {
    let dir = temp_dir("items-grow-bad");
    let out = dir.join("out");
    for (method, env, want) in [
        ("adaptive:scope=local,items_grow=maybe", None, "error: adaptive: items_grow = `maybe`: use `on` or `off`\n"),
        ("adaptive:items_grow=off", None, "error: adaptive: items_grow needs scope = local (only it keeps an item list)\n"),
        ("adaptive:scope=local", Some("many"), "error: PENUMBRA_ITEMS_FIXED = `many`: use a whole number of items, at least 1\n"),
    ] {
        let args = ["render", "--scene", "slat-roof", "--set", "resolution=32", "--method", method, "--out", out.to_str().unwrap()];
        let o = match env {
            Some(v) => common::penumbra_env(&args, &[("PENUMBRA_ITEMS_FIXED", v)]),
            None => penumbra(&args),
        };
        assert_eq!((o.status.code(), String::from_utf8_lossy(&o.stderr).as_ref()), (Some(1), want), "{method}");
        assert!(!out.exists(), "{method}: nothing written");
    }
}
