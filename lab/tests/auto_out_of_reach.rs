//! `auto:target=T` where no grid reaches the target (docs/error-estimate.md §6): the one-map
//! candidates are read against the grid the frame would render, and one read no worse than it is
//! rendered instead. Alone in its file: the check's time rule (a candidate must render quicker
//! than the grid's try) compares two wall clocks, which the other tests' renders would share.

mod common;
use penumbra::research::frame::{FrameOptions, Renderer};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::auto::AutoRecord;
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;

fn options() -> FrameOptions {
    FrameOptions {
        mode: TimingMode::Frame,
        pictures: false,
    }
}

/// A frame's record read as auto's, typed.
fn auto(record: &serde_json::Value) -> AutoRecord {
    AutoRecord::read(record).unwrap_or_else(|| panic!("not auto's record: {record}"))
}

fn tempfile_dir(name: &str) -> std::path::PathBuf {
    common::temp_dir(name).join("out")
}

/// Where no grid reaches the target (`grazing-ground`, acne-prone, with n ≤ 4 and 1024² maps), the
/// default candidates are read against the grid the frame would render, and one that differs from
/// it by at most the grid's predicted RMSE is rendered: msm, which errs less than the grid; pcss
/// differs by more and is not taken. Its V is
/// msm's, bit for bit, in the settling and the settled frame; the bound is |V_msm − V_grid| plus
/// the grid's bound. On a point light the default list leaves msm out, and a list naming it is
/// refused.
#[test]
fn auto_renders_a_filter_where_no_grid_reaches_the_target() {
    let ctx = common::gpu();
    let sets = [("resolution".to_string(), "64".to_string())];
    let scene = Scene::load("grazing-ground", &sets).unwrap();
    let spec = "auto:target=0.03,max_n=4,max_size=1024,cost=texels,pixels=0";
    let msm = penumbra::research::frame::render(
        ctx,
        &scene,
        &Method::parse("msm", &[]).unwrap(),
        options(),
    )
    .unwrap();
    let mut r = Renderer::new(ctx, &scene, &Method::parse(spec, &[]).unwrap()).unwrap();
    let first = r.frame(options()).unwrap();
    let rec = &first.output.record;
    let a = auto(rec);
    println!("first frame: {}", serde_json::to_string(rec).unwrap());
    let filter = a.filter.as_ref().expect("the one-map check ran");
    assert_eq!(
        (
            a.target_met,
            a.renders.as_deref(),
            filter.chosen.as_deref(),
            &filter.reference
        ),
        (false, Some("msm"), Some("msm"), &None),
        "{rec}"
    );
    let grid_rmse = a.tries.last().unwrap().prediction.predicted_rmse;
    let checks = &filter.checks;
    assert_eq!(
        checks.iter().map(|c| c.method.as_str()).collect::<Vec<_>>(),
        ["pcss", "msm"],
        "{rec}"
    );
    let d = |c: &penumbra::research::methods::auto::Check| c.difference.unwrap();
    assert!(
        d(&checks[1]) <= grid_rmse && checks[1].accepted,
        "msm within the grid's {grid_rmse}: {rec}"
    );
    assert!(
        d(&checks[0]) > grid_rmse && !checks[0].accepted,
        "pcss differs by more than the grid's {grid_rmse}: {rec}"
    );
    assert_eq!(
        a.predicted_rmse, grid_rmse,
        "the grid's prediction stays: {rec}"
    );
    assert!(
        first.visibility == msm.visibility,
        "the settling frame's V is msm's"
    );
    let tries_maps: u32 = a.tries.iter().map(|t| t.maps).sum();
    assert!(
        checks.iter().all(|c| c.maps == 2),
        "an untimed first render and the timed one: {rec}"
    );
    assert_eq!(
        first.output.shadow_maps,
        tries_maps + 4,
        "the tries, and two maps per candidate: {rec}"
    );
    // The bound: |V_msm − V_grid| plus the grid's own bound.
    let (n, size) = (a.chosen.n, a.chosen.map_size);
    let mut grid_sets = sets.to_vec();
    grid_sets.push(("shadow_map_size".into(), size.to_string()));
    let grid = penumbra::research::frame::render(
        ctx,
        &Scene::load("grazing-ground", &grid_sets).unwrap(),
        &Method::parse(&format!("regular:n={n},layout=centred,estimate=on"), &[]).unwrap(),
        options(),
    )
    .unwrap();
    let (bound, grid_bound) = (
        first.output.bound.clone().unwrap(),
        grid.output.bound.clone().unwrap(),
    );
    for i in 0..bound.len() {
        let expect = if grid_bound[i] > 0.0 {
            (msm.visibility[i] - grid.visibility[i]).abs() + grid_bound[i]
        } else {
            0.0
        };
        assert!(
            (bound[i] - expect).abs() < 1e-5,
            "pixel {i}: bound {} against {expect}",
            bound[i]
        );
    }
    let second = r.frame(options()).unwrap();
    assert_eq!(
        (
            second.output.shadow_maps,
            auto(&second.output.record).estimated
        ),
        (1, false),
        "{}",
        second.output.record
    );
    assert!(
        second.visibility == msm.visibility,
        "the settled frame renders msm alone"
    );

    // Measured against the reference: msm errs less than the grid auto could not take further.
    let out = tempfile_dir("auto-out-of-reach");
    let measured = |methods: &str, sets: &[&str], dir: &str| -> f64 {
        let out = out.join(dir);
        let mut args = vec![
            "compare",
            "--scene",
            "grazing-ground",
            "--set",
            "resolution=64",
            "--repeats",
            "1",
            "--methods",
            methods,
            "--out",
            out.to_str().unwrap(),
        ];
        for s in sets {
            args.extend(["--set", s]);
        }
        let o = common::penumbra(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        if methods == spec {
            assert!(
                String::from_utf8_lossy(&o.stderr).contains("; msm differs from that grid by"),
                "{}",
                String::from_utf8_lossy(&o.stderr)
            );
        }
        let row = penumbra_lab::record::ResultRow::from_json(
            std::fs::read_to_string(out.join("results.jsonl"))
                .unwrap()
                .lines()
                .next()
                .unwrap(),
        )
        .unwrap();
        assert_eq!(row.core.rmse, row.metrics.rmse);
        row.metrics.rmse
    };
    let grid_measured = measured(
        &format!("regular:n={n},layout=centred"),
        &[&format!("shadow_map_size={size}")],
        "grid",
    );
    let auto_measured = measured(spec, &[], "auto");
    assert!(
        auto_measured < 0.8 * grid_measured,
        "auto (msm) {auto_measured} against the grid {grid_measured}"
    );

    // A point light: msm refuses it, so the default list leaves it out; naming it is an error.
    let point = Scene::load("point-edge", &sets).unwrap();
    let p = penumbra::research::frame::render(
        ctx,
        &point,
        &Method::parse("auto:target=0.03,cost=texels,pixels=0", &[]).unwrap(),
        options(),
    )
    .unwrap();
    assert_eq!(
        auto(&p.output.record).filter.map(|f| f.left_out),
        Some(vec!["msm".to_string()]),
        "{}",
        p.output.record
    );
    let bad = tempfile_dir("auto-point-msm");
    let o = common::penumbra(&[
        "render",
        "--scene",
        "point-edge",
        "--set",
        "resolution=64",
        "--method",
        "auto:target=0.03,filters=msm,pixels=0",
        "--out",
        bad.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("filters = msm") && stderr.contains("light kind `point`"),
        "{stderr}"
    );
    assert!(!bad.exists(), "nothing written");
}
