//! scope = local's (pixel, quad) item list follows the need (robustness.md, "Item list growth"):
//! on scenes/slat-roof.toml, a periodic occluder whose penumbrae never end, the default list
//! overflows at level 2; the frame runs again on a grown list, and V is the V of a list large
//! enough from the start, bit for bit.

mod common;
use common::{ok, penumbra, temp_dir};
use penumbra::research::frame::Renderer;
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;

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
    let out = penumbra(&[
        "render",
        "--scene",
        "slat-roof",
        "--method",
        "adaptive:scope=local,items_grow=off",
        "--warm-up",
        "0",
        "--out",
        d,
    ]);
    let e = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{e}");
    assert_eq!(e, "error: overflow: adaptive level 2: the (pixel, quad) item list exceeded its capacity (flags 0x2); the run is not valid\n");
    assert!(!dir.exists(), "a failed run writes nothing");

    // Levels 3 and 4 at 128², level 3 at 512², growth on (the default): every run completes. At
    // 512² level 3 evaluates 7,457,032 items, more than one row of list workgroups holds.
    for (res, method, levels) in [
        ("128", "adaptive:preset=seed,scope=local", 5),
        ("128", "adaptive:scope=local,max_level=3", 4),
        ("512", "adaptive:scope=local,max_level=3", 4),
    ] {
        ok(
            penumbra(&[
                "render",
                "--scene",
                "slat-roof",
                "--method",
                method,
                "--set",
                &format!("resolution={res}"),
                "--warm-up",
                "0",
                "--timing",
                "frame",
                "--out",
                d,
            ]),
            method,
        );
        let r = run_json(&dir);
        let m = &r["method_record"];
        let items = &m["items"];
        let evaluated: Vec<u64> = m["levels"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| l["pixels_evaluated"].as_u64().unwrap())
            .collect();
        println!(
            "{res}² {method}: items {items}, per level {evaluated:?}, syncs {}",
            r["syncs"]
        );
        assert_eq!(evaluated.len(), levels, "{res}² {method}");
        let capacity = items["capacity"].as_u64().unwrap();
        assert!(
            evaluated.iter().all(|&n| n <= capacity),
            "{res}² {method}: {evaluated:?} within {capacity}"
        );
        let again = items["frames_run_again"].as_u64().unwrap();
        if res == "128" {
            // Level 3 alone needs more than the default list: the frame grew it and ran again.
            assert!(evaluated[3] > DEFAULT_128, "{evaluated:?}");
            assert!(again >= 1 && capacity > DEFAULT_128, "{items}");
            // Each run that overflowed read back at least one level: counted, not hidden.
            assert!(
                r["syncs"].as_u64().unwrap() > levels as u64,
                "{}",
                r["syncs"]
            );
        } else {
            assert_eq!(
                (again, r["syncs"].as_u64()),
                (0, Some(levels as u64)),
                "{res}² {method}"
            );
            assert_eq!(evaluated[3], 7_457_032);
        }
    }
    // Level 4 at 512² needs more than one storage binding holds (on lavapipe's 128 MiB, 16,777,216
    // items): the list grows to that and the frame fails with an overflow that says so.
    let max = penumbra::research::methods::adaptive::buffers::max_items(common::gpu());
    let out = penumbra(&[
        "render",
        "--scene",
        "slat-roof",
        "--method",
        "adaptive:preset=seed,scope=local",
        "--set",
        "resolution=512",
        "--warm-up",
        "0",
        "--timing",
        "frame",
        "--out",
        d,
    ]);
    let e = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{e}");
    let want = format!("error: overflow: adaptive scope=local at 512x512: a level needs at least 24275952 (pixel, quad) items, more than the {max} one storage binding holds on this device; the run is not valid (use a smaller resolution, a lower max_level or scope=global)\n");
    if max < 24_275_952 {
        assert_eq!(e, want);
    } else {
        assert!(out.status.success(), "{e}");
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
            (
                f.visibility.iter().map(|v| v.to_bits()).collect(),
                f.output.record,
                f.output.syncs,
            )
        })
        .collect()
}

#[test]
fn a_grown_list_gives_the_v_of_a_list_that_fitted_bit_for_bit() {
    // 4M items hold every level of the seed setting (2.4M at level 4): nothing grows.
    let (fits, rec, syncs) = frames("adaptive:preset=seed,scope=local,items=4000000", 1).remove(0);
    assert_eq!(
        rec["items"],
        serde_json::json!({ "capacity": 4_000_000, "frames_run_again": 0, "grown_to": [] })
    );
    assert_eq!(syncs, 5);
    for spec in [
        "adaptive:preset=seed,scope=local",
        "adaptive:preset=seed,scope=local,items=5000",
        "adaptive:preset=seed,scope=local,items=5000,steer=gpu",
    ] {
        let runs = frames(spec, 2);
        let (v, rec, syncs) = &runs[0];
        let items = &rec["items"];
        let grown: Vec<u64> = items["grown_to"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_u64().unwrap())
            .collect();
        println!("{spec}: {items}, syncs {syncs}");
        assert!(v == &fits, "{spec}: V differs from the run that fitted");
        assert!(
            !grown.is_empty() && grown.windows(2).all(|w| w[0] < w[1]),
            "{spec}: {items}"
        );
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
        assert_eq!(
            (
                rec2["items"]["frames_run_again"].as_u64(),
                rec2["items"]["capacity"].as_u64()
            ),
            (Some(0), grown.last().copied())
        );
        assert_eq!(*syncs2, if spec.contains("steer=gpu") { 0 } else { 5 });
    }
}

#[test]
fn growth_settings_refuse_bad_values_in_one_line() {
    let dir = temp_dir("items-grow-bad");
    let out = dir.join("out");
    for (method, env, want) in [
        (
            "adaptive:scope=local,items_grow=maybe",
            None,
            "error: adaptive: items_grow = `maybe`: use `on` or `off`\n",
        ),
        (
            "adaptive:items_grow=off",
            None,
            "error: adaptive: items_grow needs scope = local (only it keeps an item list)\n",
        ),
        (
            "adaptive:scope=local",
            Some("many"),
            "error: PENUMBRA_ITEMS_FIXED = `many`: use a whole number of items, at least 1\n",
        ),
    ] {
        let args = [
            "render",
            "--scene",
            "slat-roof",
            "--set",
            "resolution=32",
            "--method",
            method,
            "--out",
            out.to_str().unwrap(),
        ];
        let o = match env {
            Some(v) => common::penumbra_env(&args, &[("PENUMBRA_ITEMS_FIXED", v)]),
            None => penumbra(&args),
        };
        assert_eq!(
            (o.status.code(), String::from_utf8_lossy(&o.stderr).as_ref()),
            (Some(1), want),
            "{method}"
        );
        assert!(!out.exists(), "{method}: nothing written");
    }
}

/// reproject_count's and probe's `begin` size the list passes: past 65,535 workgroups of 64 items
/// (4,194,240) the workgroups go on in rows, which one dimension alone cannot hold (an indirect
/// dispatch over the limit is dropped whole). Both equal their twin exactly, around each edge.
#[test]
fn list_dispatches_past_one_dimension_equal_their_twin() {
    use penumbra::research::gpu::readback;
    use penumbra::research::gpu::structs::{GpuControl, GpuSample};
    use penumbra::research::methods::adaptive::buffers::{
        list_dispatch, AdaptiveBuffers, LATTICE_POINTS,
    };
    use penumbra::research::methods::adaptive::level_uniform;
    use penumbra::research::stages::{probe::Probe, reproject_count::ReprojectCount};
    let ctx = common::gpu();
    let b = AdaptiveBuffers::new(
        ctx,
        8,
        8,
        &[GpuSample::default(); LATTICE_POINTS as usize],
        true,
        None,
    )
    .unwrap();
    let shape = penumbra::research::methods::adaptive::buffers::Shape {
        item_capacity: u32::MAX,
        ..b.shape
    };
    let level = readback::uniform_buffer(
        ctx,
        "level",
        &level_uniform(
            &penumbra::research::methods::AdaptiveParams::default(),
            shape,
            1,
            1,
            0,
        ),
    );
    let (count, probe) = (ReprojectCount::new(ctx).unwrap(), Probe::new(ctx).unwrap());
    let edge = 65_535 * 64;
    for n in [
        0u32,
        1,
        64,
        65,
        edge - 1,
        edge,
        edge + 1,
        7_457_032,
        2 * edge + 64,
        u32::MAX - 63,
    ] {
        let control = GpuControl {
            item_count: n,
            probe_count: n,
            ..Default::default()
        };
        ctx.queue
            .write_buffer(&b.control, 0, bytemuck::bytes_of(&control));
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        probe.record_begin(ctx, &mut enc, &level, &b.control, &b.items);
        count.record_begin(ctx, &mut enc, &level, &b.control, &b.items);
        ctx.queue.submit([enc.finish()]);
        let read = |buf: &wgpu::Buffer, words: u64| {
            readback::read_buffer::<u32>(ctx, buf, words * 4).unwrap()
        };
        let want = list_dispatch(n);
        assert_eq!(read(&b.items.list_args, 3), want, "items {n}");
        assert_eq!(read(&b.items.probe_args, 3), want, "probes {n}");
        assert_eq!(
            (read(&b.items.total, 1)[0], read(&b.items.probe_total, 1)[0]),
            (n, n),
            "{n}"
        );
        // Every item gets an invocation, and a row is only as long as the limit.
        let [x, y, _] = want;
        assert!(
            x <= 65_535 && x as u64 * y as u64 * 64 >= n as u64,
            "{n}: {want:?}"
        );
    }
    assert_eq!(list_dispatch(7_457_032), [65_535, 2, 1]);
}

/// At 512² level 3 of slat-roof evaluates 7,457,032 items: past 65,535 workgroups of 64, its list
/// passes run in two rows. Items per level and V equal the CPU twin of the local pipeline exactly
/// (before the rows, a dispatch over the limit was dropped whole and level 3 added nothing).
#[test]
fn a_list_past_one_row_of_workgroups_equals_the_local_twin() {
    use penumbra::research::frame::frame_uniform;
    use penumbra::research::stages::twin;
    let ctx = common::gpu();
    let scene = Scene::load(
        "slat-roof",
        &[("resolution".to_string(), "512".to_string())],
    )
    .unwrap();
    let method = Method::parse("adaptive:scope=local,max_level=3", &[]).unwrap();
    let p = method.adaptive_params().unwrap().clone();
    let (r, t) = common::traced(ctx, &scene, &p, true);
    let fr = frame_uniform(&scene);
    let maps = |k: u32| {
        t.maps
            .iter()
            .find(|(m, _)| *m == k)
            .expect("map kept")
            .1
            .clone()
    };
    let out = twin::local::local(&fr, &t.samples, &maps, &r.gbuffer, p.max_level, &|l| {
        p.split_rule(l)
    });
    let items: Vec<u32> = t.levels.iter().map(|l| l.items).collect();
    assert_eq!(items, [216_770, 710_172, 1_974_984, 7_457_032]);
    assert_eq!(out.items, items);
    let scale = (4u32 << (2 * p.max_level)) as f32;
    let wrong = out
        .visibility_fixed
        .iter()
        .zip(&r.visibility)
        .filter(|(a, b)| **a as f32 / scale != **b)
        .count();
    assert_eq!(wrong, 0, "{wrong} pixels differ from the twin");
}
