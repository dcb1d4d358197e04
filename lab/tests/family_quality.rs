//! What the single-map family must show: PCSS follows the penumbra of the closed form better than
//! a hard shadow and a fixed-radius PCF; VSM bleeds light where two occluders overlap and EVSM and
//! MSM bleed less.

mod common;
use glam::Vec3;
use penumbra::research::frame::{self, FrameResult};
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;
use penumbra_lab::reference::AnalyticSquareScene;

fn run(scene: &Scene, spec: &str) -> FrameResult {
    frame::render(
        common::gpu(),
        scene,
        &Method::parse(spec, &[]).unwrap(),
        TimingMode::Frame,
    )
    .unwrap()
}

#[test]
fn pcss_penumbra_beats_hard_and_fixed_radius_pcf_on_analytic_square() {
    let scene = Scene::load("analytic-square", &[("resolution".into(), "128".into())]).unwrap();
    let exact = AnalyticSquareScene {
        light_center: Vec3::new(0.0, 10.0, 0.0),
        light_side: 4.0,
        occluder_center: Vec3::new(0.0, 4.0, 0.0),
        occluder_side: 4.0,
    };
    let mut rmse = Vec::new();
    for spec in ["hard", "pcf", "pcf:kernel=box", "pcss"] {
        let r = run(&scene, spec);
        let g = &r.gbuffer;
        let (mut sq, mut n) = (0.0f64, 0usize);
        for i in 0..g.position.len() {
            if g.is_geometry(i) && g.position[i][1].abs() < 1e-4 {
                let v = exact.visibility(Vec3::from_slice(&g.position[i][..3]));
                if v > 0.01 && v < 0.99 {
                    sq += ((r.visibility[i] - v) as f64).powi(2);
                    n += 1;
                }
            }
        }
        assert!(n > 500, "{spec}: only {n} penumbra pixels");
        let e = (sq / n as f64).sqrt();
        println!("{spec}: penumbra RMSE {e:.4} over {n} pixels");
        rmse.push(e);
    }
    assert!(
        rmse[3] < rmse[0] && rmse[3] < rmse[1] && rmse[3] < rmse[2],
        "pcss {:.4} vs hard {:.4}, pcf {:.4} / {:.4}",
        rmse[3],
        rmse[0],
        rmse[1],
        rmse[2]
    );
    assert!(
        rmse[3] < 0.5 * rmse[0],
        "pcss should at least halve the hard shadow's penumbra error"
    );
}

/// Whether the segment from `p` to `q` crosses the axis-aligned box `centre ± half`.
fn segment_hits_box(p: Vec3, q: Vec3, centre: Vec3, half: Vec3) -> bool {
    let d = q - p;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for a in 0..3 {
        let (lo, hi) = (centre[a] - half[a], centre[a] + half[a]);
        if d[a].abs() < 1e-9 {
            if p[a] < lo || p[a] > hi {
                return false;
            }
            continue;
        }
        let (mut u, mut v) = ((lo - p[a]) / d[a], (hi - p[a]) / d[a]);
        if u > v {
            std::mem::swap(&mut u, &mut v);
        }
        t0 = t0.max(u);
        t1 = t1.min(v);
    }
    t0 <= t1
}

#[test]
fn vsm_bleeds_light_where_occluders_overlap_and_evsm_and_msm_reduce_it() {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("scenes/overlapping-occluders.toml");
    let scene = Scene::load(
        &file.to_string_lossy(),
        &[("resolution".into(), "128".into())],
    )
    .unwrap();
    let light = scene.light;
    let (plate_a, half_a) = (Vec3::new(-0.6, 1.0, -0.3), Vec3::new(1.0, 0.05, 1.0));
    let (plate_b, half_b) = (Vec3::new(0.5, 2.5, 0.5), Vec3::new(0.8, 0.05, 0.8));
    let corners = [
        light.point(0.0, 0.0),
        light.point(1.0, 0.0),
        light.point(0.0, 1.0),
        light.point(1.0, 1.0),
    ];
    let mut results = Vec::new();
    // A small prefilter keeps the windows on the plates: what V shows there is bleeding, not blur.
    for spec in ["vsm:radius=3", "evsm:radius=3", "msm:radius=3"] {
        let r = run(&scene, spec);
        let g = &r.gbuffer;
        // Ground pixels under both plates: plate A (convex) blocks all four light corners, so it
        // blocks the whole light and V = 0 exactly; plate B also blocks the ray to the centre.
        let region: Vec<usize> = (0..g.position.len())
            .filter(|&i| g.is_geometry(i) && g.position[i][1].abs() < 1e-4)
            .filter(|&i| {
                let p = Vec3::from_slice(&g.position[i][..3]);
                corners
                    .iter()
                    .all(|&c| segment_hits_box(p, c, plate_a, half_a))
                    && segment_hits_box(p, light.center, plate_b, half_b)
            })
            .collect();
        assert!(
            region.len() > 50,
            "only {} pixels lie under both plates",
            region.len()
        );
        let bleed =
            region.iter().map(|&i| r.visibility[i] as f64).sum::<f64>() / region.len() as f64;
        println!(
            "{spec}: mean V = {bleed:.4} (exact 0) over {} pixels under both plates",
            region.len()
        );
        results.push(bleed);
    }
    assert!(
        results[0] > 0.01,
        "vsm shows no light bleeding ({:.4}): the test would prove little",
        results[0]
    );
    assert!(
        results[1] < 0.5 * results[0],
        "evsm {:.4} does not reduce vsm's bleeding {:.4}",
        results[1],
        results[0]
    );
    assert!(
        results[2] < 0.5 * results[0],
        "msm {:.4} does not reduce vsm's bleeding {:.4}",
        results[2],
        results[0]
    );
}
