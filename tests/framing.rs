//! The framing study end to end on a small grid: rows per configuration and method, the penumbra
//! width growing with resolution and light size, and the charts written.

mod common;
use penumbra::studies::compare::methods_list;
use penumbra::studies::framing::{run, FramingJob};
use penumbra::reference::truth::Cache;
use penumbra::reference::ReferenceMode;
use penumbra::scene::Scene;

#[test]
fn framing_study_measures_width_maps_and_error_per_configuration() {
    let ctx = common::gpu();
    let sets = [("shadow_map_size".to_string(), "128".to_string())];
    let scene = Scene::load("default", &sets).unwrap();
    let methods = methods_list::parse_methods(&["regular:n=3".to_string(), "adaptive:preset=seed".to_string()]).unwrap();
    let job = FramingJob {
        scenes: vec![scene],
        resolutions: vec![64, 128],
        light_scales: vec![4.0, 8.0],
        methods,
        repeats: 1,
        reference: ReferenceMode::Continuous { m: 16, seed: 1 },
        cache: Cache::Off,
    };
    let outcome = run(ctx, &job, &|_| {}).unwrap();
    assert_eq!(outcome.rows.len(), 2 * 2 * 2, "configurations x methods");
    let width = |res: u32, scale: f32| outcome.rows.iter().find(|r| r.resolution == res && r.light_scale == scale).unwrap().penumbra_width_px.expect("a penumbra");
    let (small, fine, big) = (width(64, 4.0), width(128, 4.0), width(64, 8.0));
    println!("penumbra width: {small:.2} px at 64², {fine:.2} px at 128², {big:.2} px at 64² with a 2x larger light");
    assert!(fine > 1.4 * small, "twice the pixels should widen the penumbra on screen: {small} -> {fine}");
    assert!(big > 1.4 * small, "a 2x larger light should widen the penumbra: {small} -> {big}");
    for r in &outcome.rows {
        assert!(r.rmse.is_finite() && r.rmse > 0.0 && r.shadow_maps >= 4, "{}: {} maps, RMSE {}", r.label, r.shadow_maps, r.rmse);
        if r.label.starts_with("regular") {
            assert_eq!(r.shadow_maps, 9);
        }
    }
    let names: Vec<&str> = outcome.files.iter().map(|(n, _)| n.as_str()).collect();
    for f in ["framing.jsonl", "framing.csv", "framing.md", "charts/framing_maps.svg", "charts/framing_rmse.png", "configs/default-128px-light8/results.jsonl"] {
        assert!(names.contains(&f), "{f} missing from {names:?}");
    }
    let jsonl = &outcome.files.iter().find(|(n, _)| n == "framing.jsonl").unwrap().1;
    assert_eq!(String::from_utf8_lossy(jsonl).lines().count(), 8);
}
