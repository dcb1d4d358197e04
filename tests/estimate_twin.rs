//! The `estimate` kernel equals its CPU twin on random scenes, plain maps split into chunks by the
//! memory budget included, and the prediction in run.json is the one its sums give.

mod common;
use penumbra::research::frame::{frame_uniform, FrameOptions};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::{estimate, fixed_samples, Method};
use penumbra::research::scene::Scene;
use penumbra::research::stages::twin;

#[test]
fn estimate_equals_its_cpu_twin() {
    let ctx = common::gpu();
    for (seed, spec, budget) in [
        (5u64, "regular:n=3,layout=centred,estimate=on", "64"),
        (17, "regular:n=4,estimate=on", "1"),
        (23, "regular:n=5,layout=jittered,estimate=on", "64"),
    ] {
        let sc = Scene::parse(
            &common::random_scene_toml(seed, 48, 128),
            "random",
            None,
            &[("shadow_map_budget_mib".into(), budget.into())],
        )
        .unwrap();
        let method = Method::parse(spec, &[]).unwrap();
        let options = FrameOptions {
            mode: TimingMode::Frame,
            pictures: true,
        };
        let (r, c): (_, fixed_samples::FixedBuffers) =
            common::inspected(ctx, &sc, &method, options);
        let n = c.samples.len();
        assert_eq!(c.split.len(), n);
        let mut sums = vec![[0.0f32; 8]; r.visibility.len()];
        let set = twin::estimate::SampleSet {
            samples: &c.samples,
            weights: &c.weights,
            split: &c.split,
            maps: &c.maps,
        };
        twin::estimate::estimate(&frame_uniform(&sc), &set, &r.gbuffer, 0..n, &mut sums);
        let (mut worst, mut active) = (0.0f32, [0usize; 8]);
        for (gpu, cpu) in c.estimate_sums.iter().zip(&sums) {
            for k in 0..8 {
                worst = worst.max((gpu[k] - cpu[k]).abs());
                active[k] += (cpu[k] != 0.0) as usize;
            }
        }
        println!("seed {seed} {spec}: {n} maps, max |GPU - twin| = {worst:e}, pixels with a non-zero sum: {active:?}");
        assert!(active.iter().all(|&a| a > 10), "seed {seed}: each sum should be non-zero somewhere, or the test proves little: {active:?}");
        assert!(
            worst <= 1e-5,
            "seed {seed}: estimate differs from its twin by {worst}"
        );
        // The record's prediction is the sums' (methods::estimate::predict over the geometry pixels).
        let geometry: Vec<bool> = (0..sums.len()).map(|i| r.gbuffer.is_geometry(i)).collect();
        let layout = method.params_json()["layout"]
            .as_str()
            .map(|l| match l {
                "centred" => fixed_samples::Layout::Centred,
                "jittered" => fixed_samples::Layout::Jittered,
                _ => fixed_samples::Layout::Lattice,
            })
            .unwrap();
        let side = method.params_json()["n"].as_u64().unwrap() as u32;
        let (p, bound) = estimate::predict(&c.estimate_sums, &geometry, layout, side).unwrap();
        let rec = &r.output.record;
        for (key, value) in [
            ("predicted_rmse", p.predicted_rmse),
            ("predicted_sampling", p.predicted_sampling),
            ("predicted_map", p.predicted_map),
            ("predicted_map_averaging", p.predicted_map_averaging),
        ] {
            assert_eq!(
                rec[key].as_f64(),
                Some(value),
                "seed {seed}: run record's {key}"
            );
        }
        assert!(
            p.predicted_sampling > 0.0 && p.predicted_map > 0.0 && p.predicted_map_averaging > 0.0
        );
        assert!(bound.iter().zip(&geometry).all(|(b, g)| if *g {
            *b >= estimate::BOUND_FLOOR
        } else {
            *b == 0.0
        }));
        assert_eq!(
            r.output.bound.as_deref(),
            Some(&bound[..]),
            "seed {seed}: the frame's bound is the sums'"
        );
    }
}

#[test]
fn estimate_is_refused_with_cull_and_on_bad_values() {
    for (spec, expect) in [
        ("regular:n=3,estimate=yes", "estimate = `yes`"),
        ("regular:n=3,estimate=on,cull=on", "use one of them"),
    ] {
        let err = Method::parse(spec, &[])
            .err()
            .unwrap_or_else(|| panic!("{spec} parsed"))
            .to_string();
        assert!(
            err.contains(expect) && err.contains("regular"),
            "{spec}: {err}"
        );
    }
}
