//! Analytic checks of environment lighting (docs/environment.md §3): an unoccluded point under a
//! uniform environment receives πL; under a single-pixel environment, that pixel's cosine term;
//! a point on the ground beside a wall under a uniform sky sees V = ½(1 + d/√(d² + h²)). The CPU
//! reference meets each within its stated Monte Carlo error, and env-pixels on the GPU meets the
//! wall's closed form within its discretisation.

mod common;
use glam::Vec3;
use penumbra::research::scene::environment::panorama::band_solid_angle;
use penumbra::research::scene::environment::{Environment, Panorama};
use penumbra_lab::reference::environment::{self, PanoramaSampler};
use penumbra_lab::reference::sampling::PixelRng;
use penumbra_lab::reference::{SurfacePoint, Tracer};
use std::f64::consts::PI;

/// Irradiance by importance sampling: E = P · mean(max(0, n·ω)), P the panorama's power.
fn sampled_irradiance(env: &Environment, n: Vec3, samples: u32) -> (f64, f64) {
    let sampler = PanoramaSampler::new(env);
    let mut rng = PixelRng::new(7, 0);
    let values: Vec<f64> = (0..samples)
        .map(|k| {
            let a = (k as f32 + rng.next_f32()) / samples as f32;
            let d = sampler.sample(env, a.min(0.99999994), rng.next_f32(), rng.next_f32());
            sampler.total() * n.dot(d).max(0.0) as f64
        })
        .collect();
    let mean = values.iter().sum::<f64>() / samples as f64;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (samples - 1) as f64;
    (mean, (var / samples as f64).sqrt())
}

#[test]
fn unoccluded_point_under_a_uniform_environment_receives_pi_l() {
    let l = 1.7f32;
    let env = Environment::new("uniform", Panorama::uniform(128, 64, [l; 3]), 0.0, 1.0);
    for n in [
        Vec3::Y,
        Vec3::new(0.6, 0.0, 0.8),
        Vec3::new(-0.2, -0.9, 0.3).normalize(),
    ] {
        let (e, se) = sampled_irradiance(&env, n, 4096);
        let exact = PI * l as f64;
        println!("n {n}: E = {e:.4} ± {se:.4} (πL = {exact:.4})");
        // Stratified sampling: the standard error of plain sampling bounds the error from above.
        assert!(
            (e - exact).abs() < 4.0 * se && se < 0.03 * exact,
            "n {n}: E = {e} ± {se}, πL = {exact}"
        );
        // And V = 1 with nothing to block it.
        let tracer = Tracer::new(&[]);
        let p = SurfacePoint {
            position: Vec3::ZERO,
            normal: n,
        };
        let (v, err, rays) = environment::point(
            &tracer,
            &env,
            &PanoramaSampler::new(&env),
            &p,
            256,
            1e-4,
            100.0,
            PixelRng::new(1, 2),
        );
        assert_eq!((v, err), (1.0, 0.0));
        assert!(rays > 100);
    }
}

#[test]
fn single_pixel_environment_gives_its_cosine_term() {
    let (w, h) = (64u32, 32u32);
    let mut p = Panorama::uniform(w, h, [0.0; 3]);
    let (x, y) = (40u32, 9u32);
    let l = 30.0f32;
    p.rgb[(y * w + x) as usize] = [l; 3];
    let env = Environment::new("one pixel", p, 20.0, 1.0);
    let centre = env.direction((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
    let angle = band_solid_angle(y as f32 / h as f32, (y + 1) as f32 / h as f32, w) as f64;
    for n in [Vec3::Y, centre, Vec3::new(0.5, 0.5, -0.2).normalize()] {
        let exact = l as f64 * angle * n.dot(centre).max(0.0) as f64;
        let (e, _) = sampled_irradiance(&env, n, 4096);
        // Samples spread over the pixel: the cosine varies by at most the pixel's angular size.
        let pixel = (std::f64::consts::PI / h as f64) * 1.5;
        println!("n {n}: E = {e:.5}, L·Δω·cos = {exact:.5}");
        assert!(
            (e - exact).abs() <= l as f64 * angle * pixel,
            "n {n}: {e} vs {exact}"
        );
    }
    // A plate across that direction blocks all of it: V = 0; beside it, V = 1.
    let plate = |c: Vec3| {
        let (u, v) = (
            centre.any_orthonormal_vector(),
            centre.cross(centre.any_orthonormal_vector()),
        );
        let c = c + centre * 2.0;
        vec![
            [c - u - v, c + u - v, c + u + v],
            [c - u - v, c + u + v, c - u + v],
        ]
    };
    let tracer = Tracer::new(&plate(Vec3::ZERO));
    let at = |q: Vec3| {
        environment::point(
            &tracer,
            &env,
            &PanoramaSampler::new(&env),
            &SurfacePoint {
                position: q,
                normal: Vec3::Y,
            },
            64,
            1e-4,
            100.0,
            PixelRng::new(3, 4),
        )
        .0
    };
    assert_eq!(at(Vec3::ZERO), 0.0);
    assert_eq!(
        at(Vec3::new(0.0, 0.0, 0.0) + centre.any_orthonormal_vector() * 5.0),
        1.0
    );
}

/// Ground point at distance d from a wall of height h (plane x = 0, infinitely long in z) under a
/// uniform sky: the wall hides ½(1 − d/√(d² + h²)) of the cosine-weighted hemisphere.
pub fn wall_visibility(d: f64, h: f64) -> f64 {
    0.5 * (1.0 + d / (d * d + h * h).sqrt())
}

#[test]
fn point_beside_an_infinite_wall_under_a_uniform_sky() {
    let env = Environment::new("uniform", Panorama::uniform(256, 128, [1.0; 3]), 0.0, 1.0);
    let (h, len) = (1.0f32, 4000.0f32);
    let wall = vec![
        [
            Vec3::new(0.0, 0.0, -len),
            Vec3::new(0.0, h, -len),
            Vec3::new(0.0, h, len),
        ],
        [
            Vec3::new(0.0, 0.0, -len),
            Vec3::new(0.0, h, len),
            Vec3::new(0.0, 0.0, len),
        ],
    ];
    let tracer = Tracer::new(&wall);
    let sampler = PanoramaSampler::new(&env);
    for d in [0.25f32, 1.0, 3.0] {
        let exact = wall_visibility(d as f64, h as f64);
        let p = SurfacePoint {
            position: Vec3::new(d, 0.0, 0.0),
            normal: Vec3::Y,
        };
        let (v, se, _) = environment::point(
            &tracer,
            &env,
            &sampler,
            &p,
            4096,
            1e-4,
            1e5,
            PixelRng::new(11, d.to_bits() as u64),
        );
        // The Riemann sum over pixel centres with the exact blocking test.
        let riemann = environment::riemann_visibility(&env, Vec3::Y, &|w| {
            w.x < 0.0 && (w.y as f64) / (-(w.x as f64)) < h as f64 / d as f64
        });
        println!("d {d}: reference {v:.4} ± {se:.4}, Riemann {riemann:.4}, closed form {exact:.4}");
        assert!(
            (v as f64 - exact).abs() < 4.0 * se as f64 + 1e-3,
            "d {d}: reference {v} ± {se}, closed form {exact}"
        );
        assert!(se < 0.02, "d {d}: standard error {se}");
        assert!(
            (riemann - exact).abs() < 5e-3,
            "d {d}: Riemann {riemann}, closed form {exact}"
        );
    }
}

/// On the GPU: env-pixels under a uniform sky beside a long wall meets the closed form at every
/// ground pixel within the 64x32 pixel lights' discretisation.
#[test]
fn env_pixels_beside_a_wall_meets_the_closed_form() {
    let ctx = common::gpu();
    let dir = common::temp_dir("env_wall");
    image::Rgb32FImage::from_pixel(64, 32, image::Rgb([1.0, 1.0, 1.0]))
        .save_with_format(dir.join("sky.exr"), image::ImageFormat::OpenExr)
        .unwrap();
    let text = "[camera]\neye = [2.0, 7.0, 0.5]\ntarget = [2.0, 0.0, 0.0]\nfov_y_deg = 40.0\n\n\
                [environment]\npanorama = \"sky.exr\"\n\n[render]\nwidth = 48\nheight = 48\n\n\
                [[mesh]]\nbuiltin = \"plane\"\nscale = [60.0, 1.0, 60.0]\n\n\
                [[mesh]]\nbuiltin = \"box\"\ntranslate = [-0.05, 0.5, 0.0]\nscale = [0.1, 1.0, 400.0]\n";
    let path = dir.join("wall.toml");
    std::fs::write(&path, text).unwrap();
    let scene = penumbra::research::scene::Scene::load(path.to_str().unwrap(), &[]).unwrap();
    let options = penumbra::research::frame::FrameOptions {
        mode: penumbra::research::gpu::timing::TimingMode::Frame,
        pictures: false,
    };
    let method = penumbra::research::methods::Method::parse("env-pixels:res=64x32", &[]).unwrap();
    let r = penumbra::research::frame::render(ctx, &scene, &method, options).unwrap();
    let (mut worst, mut sum, mut n) = (0.0f64, 0.0f64, 0usize);
    for i in 0..r.visibility.len() {
        let p = r.gbuffer.position[i];
        // Ground pixels beside the wall (its face is x = 0).
        if !r.gbuffer.is_geometry(i) || p[1].abs() > 1e-3 || p[0] < 0.05 {
            continue;
        }
        let err = (r.visibility[i] as f64 - wall_visibility(p[0] as f64, 1.0)).abs();
        worst = worst.max(err);
        sum += err;
        n += 1;
    }
    println!(
        "{n} ground pixels: mean |V − closed form| {:.4}, max {worst:.4}",
        sum / n as f64
    );
    assert!(n > 500, "only {n} ground pixels in view");
    let mean = sum / n as f64;
    assert!(
        mean < 0.01 && worst < 0.03,
        "mean {mean:.4}, max {worst:.4}"
    );
}
