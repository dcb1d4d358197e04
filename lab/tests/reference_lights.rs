//! The ground truth for each light kind against its scene's closed form (docs/lights.md §3),
//! traced from the GPU's own G-buffer as `penumbra reference` does: the continuous reference
//! (32×32) within MAE 2e-3 of the exact V on `disk-bar`, `sun-edge`, `point-edge`, `spot-edge`.

mod common;
use glam::{DVec3, Vec3};
use penumbra::research::frame;
use penumbra::research::scene::{Emitter, LightKind, Scene};
use penumbra_lab::reference::analytic_lights::{DiskOverBar, SphereOverEdge, SunOverEdge};
use penumbra_lab::reference::truth::{self, Cache};
use penumbra_lab::reference::ReferenceMode;

/// The closed form of each scene, from the scene's own emitter and the occluders its file states.
fn exact(scene: &Scene) -> Box<dyn Fn(DVec3) -> f64> {
    match scene.emitter {
        Emitter::Disk(d) => {
            let f = DiskOverBar {
                light_center: d.center.as_dvec3(),
                radius: d.radius as f64,
                x0: -0.5,
                x1: 0.5,
                height: 3.0,
            };
            Box::new(move |p| f.visibility(p))
        }
        Emitter::Sun(s) => {
            let f = SunOverEdge {
                toward: s.toward().as_dvec3(),
                tan_half: s.tan_half_angle() as f64,
                height: 4.0,
                edge_x: 0.0,
            };
            Box::new(move |p| f.visibility(p))
        }
        Emitter::Point(l) => {
            let f = SphereOverEdge {
                center: l.position.as_dvec3(),
                radius: l.radius as f64,
                height: 3.0,
                edge_x: 0.0,
            };
            Box::new(move |p| f.visibility(p))
        }
        Emitter::Spot(l) => {
            let f = SphereOverEdge {
                center: l.position.as_dvec3(),
                radius: l.radius as f64,
                height: 2.5,
                edge_x: -0.5,
            };
            Box::new(move |p| f.visibility(p))
        }
        Emitter::Rect => panic!("{}: a rectangle", scene.name),
    }
}

/// Ground pixels (y = 0, facing up) and their G-buffer positions, lifted to the ray origin.
fn ground_pixels(
    g: &penumbra::research::render::gbuffer::GBufferCpu,
    offset: f32,
) -> Vec<(usize, Vec3)> {
    (0..g.position.len())
        .filter(|&i| g.is_geometry(i) && g.position[i][1].abs() < 1e-4 && g.normal[i][1] > 0.99)
        .map(|i| (i, Vec3::from_slice(&g.position[i][..3]) + Vec3::Y * offset))
        .collect()
}

#[test]
fn continuous_reference_matches_each_kinds_closed_form() {
    let ctx = common::gpu();
    // The bound is the issue's, 2e-3. Measured (96², 32×32 samples, MAE over all ground pixels;
    // the deterministic seed makes these exact reruns): disk-bar 2.65e-4, sun-edge 2.62e-4,
    // point-edge 5.87e-4, spot-edge 1.63e-4 (docs/lights.md §3).
    for (name, kind, measured) in [
        ("disk-bar", LightKind::Disk, 2.65e-4),
        ("sun-edge", LightKind::Sun, 2.62e-4),
        ("point-edge", LightKind::Point, 5.87e-4),
        ("spot-edge", LightKind::Spot, 1.63e-4),
    ] {
        let scene = Scene::load(name, &[("resolution".into(), "96".into())]).unwrap();
        assert_eq!(scene.emitter.kind(), kind, "{name}");
        let exact = exact(&scene);
        let g = frame::gbuffer_only(ctx, &scene).unwrap();
        let r = truth::compute(&scene, &g, ReferenceMode::DEFAULT_CONTINUOUS, &Cache::Off).unwrap();
        let ground = ground_pixels(&g, r.ray_offset);
        let (mut sum, mut sum_penumbra, mut penumbra, mut max) = (0.0f64, 0.0f64, 0usize, 0.0f64);
        for &(i, p) in &ground {
            let v = exact(p.as_dvec3());
            let err = (r.values[i] as f64 - v).abs();
            sum += err;
            max = max.max(err);
            if v > 0.0 && v < 1.0 {
                penumbra += 1;
                sum_penumbra += err;
            }
        }
        let mae = sum / ground.len() as f64;
        println!(
            "{name}: continuous 32x32 MAE {mae:.2e} over {} ground pixels, {:.2e} over the {penumbra} in the penumbra, max {max:.2e}",
            ground.len(),
            sum_penumbra / penumbra.max(1) as f64
        );
        assert!(
            ground.len() > 3000,
            "{name}: only {} ground pixels",
            ground.len()
        );
        assert!(
            penumbra > 300,
            "{name}: only {penumbra} penumbra pixels: the camera misses the shadow"
        );
        assert!(mae < 2e-3, "{name}: MAE {mae}");
        // Same seed, same G-buffer: a change in the sampling shows here first.
        assert!(
            (mae - measured).abs() < 0.2 * measured,
            "{name}: MAE {mae:.3e}, measured {measured:.3e} before"
        );
    }
}

#[test]
fn penumbra_reference_traces_and_caches_another_kind() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let dir = common::temp_dir("reference_lights_cli");
    let cache = dir.join("cache");
    let run = |scene: &str, out: &str| {
        let out = dir.join(out);
        let args = [
            "reference",
            "--scene",
            scene,
            "--set",
            "resolution=48",
            "--samples",
            "8",
            "--out",
            out.to_str().unwrap(),
        ];
        let o = common::penumbra_env(&args, &[("PENUMBRA_CACHE", cache.to_str().unwrap())]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let record: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("reference.json")).unwrap()).unwrap();
        assert!(out.join("reference.exr").is_file() && out.join("reference_shaded.png").is_file());
        record
    };
    let first = run("point-edge", "a");
    assert_eq!(first["cached"], false);
    let again = run("point-edge", "b");
    assert_eq!(
        (again["cached"].clone(), again["key"].clone()),
        (serde_json::Value::Bool(true), first["key"].clone())
    );
    // The same occluder under another sphere: another key, traced afresh.
    let spot = run("spot-edge", "c");
    assert_ne!(spot["key"], first["key"]);
    assert_eq!(spot["cached"], false);
}

#[test]
fn building_a_rectangle_method_on_another_kind_is_refused() {
    let ctx = common::gpu();
    // The filtered maps run on the disk, the sun and the spot, not on the point's cube maps.
    let scene = Scene::load("point-edge", &[("resolution".into(), "32".into())]).unwrap();
    for spec in ["vsm", "esm", "csm"] {
        let method = penumbra::research::methods::Method::parse(spec, &[]).unwrap();
        let e = frame::Renderer::new(ctx, &scene, &method)
            .err()
            .unwrap_or_else(|| panic!("{spec} built on a point light"))
            .to_string();
        assert!(
            e.starts_with(&format!(
                "{}: light kind `point` is not supported yet (",
                method.name()
            )),
            "{e}"
        );
    }
}
