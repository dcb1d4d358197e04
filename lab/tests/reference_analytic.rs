//! The ground truth against the closed forms of method.md §5 on the analytic-square family,
//! traced from the GPU's own G-buffer exactly as `penumbra reference` does: the continuous
//! reference (32×32) within MAE 2e-3 of the exact V, the lattice reference equal to the
//! closed-form lattice count at every ground pixel whose segments clear the occluder's edges.

mod common;
use glam::Vec3;
use penumbra::research::frame;
use penumbra::research::scene::Scene;
use penumbra_lab::reference::truth::{self, Cache};
use penumbra_lab::reference::{AnalyticSquareScene, ReferenceMode};

/// Lattice segments closer than this (world units, in the occluder plane) to an occluder edge
/// are decided by f32 rounding, not geometry: such pixels are skipped and counted.
const MIN_LATTICE_MARGIN: f64 = 1e-4;

/// An analytic-square scene: light of side `b` at `light`, occluder of side `a` at `occluder`.
fn scene_text(light: [f32; 3], b: f32, occluder: [f32; 3], a: f32) -> String {
    format!(
        r#"
[camera]
eye = [0.0, 16.0, 14.0]
target = [0.0, 0.0, -1.0]
fov_y_deg = 50.0
[light]
center = {light:?}
edge_u = [{b}, 0.0, 0.0]
edge_v = [0.0, 0.0, {b}]
[render]
width = 96
height = 96
shadow_map_size = 256
cull = "none"
[[mesh]]
builtin = "plane"
scale = [30.0, 1.0, 30.0]
[[mesh]]
builtin = "plane"
translate = {occluder:?}
scale = [{a}, 1.0, {a}]
"#
    )
}

/// The built-in scene plus three more sizes and heights: a wide soft penumbra (big light, small
/// occluder near it: no umbra), a low occluder bigger than the light (a large umbra), and
/// off-centre light and occluder.
fn family() -> Vec<(&'static str, Scene, AnalyticSquareScene)> {
    let analytic = |l: [f32; 3], b, o: [f32; 3], a| AnalyticSquareScene {
        light_center: Vec3::from(l),
        light_side: b,
        occluder_center: Vec3::from(o),
        occluder_side: a,
    };
    let parse = |name, l, b, o, a| {
        let scene = Scene::parse(&scene_text(l, b, o, a), name, None, &[]).unwrap();
        (name, scene, analytic(l, b, o, a))
    };
    vec![
        (
            "analytic-square",
            Scene::load("analytic-square", &[("resolution".into(), "96".into())]).unwrap(),
            analytic([0.0, 10.0, 0.0], 4.0, [0.0, 4.0, 0.0], 4.0),
        ),
        parse("wide penumbra", [0.0, 6.0, 0.0], 6.0, [-0.4, 4.5, 0.3], 1.5),
        parse(
            "low big occluder",
            [0.5, 9.0, 0.0],
            4.0,
            [0.0, 2.5, 0.0],
            5.0,
        ),
        parse("off centre", [1.0, 8.0, -0.5], 3.0, [0.3, 3.0, 0.2], 2.5),
    ]
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
fn continuous_reference_matches_the_closed_form() {
    let ctx = common::gpu();
    for (name, scene, exact) in family() {
        let g = frame::gbuffer_only(ctx, &scene).unwrap();
        let r = truth::compute(&scene, &g, ReferenceMode::DEFAULT_CONTINUOUS, &Cache::Off).unwrap();
        let ground = ground_pixels(&g, r.ray_offset);
        let (mut sum, mut sum_penumbra, mut penumbra, mut max) = (0.0f64, 0.0f64, 0usize, 0.0f64);
        for &(i, p) in &ground {
            let v = exact.visibility(p) as f64;
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
    }
}

#[test]
fn lattice_reference_equals_the_closed_form_count() {
    let ctx = common::gpu();
    for (name, scene, exact) in family() {
        let g = frame::gbuffer_only(ctx, &scene).unwrap();
        let r = truth::compute(&scene, &g, ReferenceMode::Lattice, &Cache::Off).unwrap();
        let ground = ground_pixels(&g, r.ray_offset);
        let (mut compared, mut skipped, mut partial, mut wrong) = (0, 0, 0, Vec::new());
        for &(i, p) in &ground {
            if exact.lattice_margin(p) < MIN_LATTICE_MARGIN {
                skipped += 1;
                continue;
            }
            let v = exact.lattice_visibility(p);
            compared += 1;
            partial += (v > 0.0 && v < 1.0) as usize;
            if r.values[i] != v {
                wrong.push((i, r.values[i], v));
            }
        }
        println!("{name}: lattice compared {compared} ground pixels ({partial} partly lit), skipped {skipped} at ties");
        assert!(
            skipped * 50 < ground.len(),
            "{name}: {skipped} of {} pixels at a tie",
            ground.len()
        );
        assert!(partial > 300, "{name}: only {partial} partly lit pixels");
        assert!(
            wrong.is_empty(),
            "{name}: {} pixels differ, first (pixel, traced, exact): {:?}",
            wrong.len(),
            &wrong[..wrong.len().min(5)]
        );
    }
}
