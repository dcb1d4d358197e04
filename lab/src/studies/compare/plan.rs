//! Before a sweep (or a compare of many methods) measures anything: one line with the number of
//! configurations and an estimate of the run time, and the limit on that number
//! (`--max-configs`).

use crate::methods::Method;
use crate::record::measure;
use crate::scene::Scene;
use crate::{Error, Result};

/// Configurations one run measures unless `--max-configs` raises it. At the measured 0.5 s per
/// adaptive configuration at 64² on a 2-core CPU device (docs/robustness.md, "Sweep memory"),
/// 10,000 is about an hour and a half, and their 60,000 result files are held in memory until the
/// set is written; a grid past that is more often one axis too many than a plan.
pub const DEFAULT_MAX_CONFIGS: usize = 10_000;

/// `compare` prints the line only for more methods than this; `sweep` always does.
pub const COMPARE_ANNOUNCE_OVER: usize = 16;

/// Seconds a configuration costs besides its frames (building its pipelines and buffers, judging
/// its last frame, encoding its files): sweeps of 40 and 400 adaptive configurations on
/// `analytic-square` at 64², whose frames cost next to nothing, took 0.5 s each (llvmpipe, 2
/// cores, wall clock).
const CONFIG_S: f64 = 0.5;
/// Seconds per unit of `estimated_cost` (per map: a triangle rasterized, or `PIXEL_WEIGHT`
/// pixels shaded) per frame: the fixed-function raster of `bunny-seed-framing` (1.2 M triangles)
/// took 87 ms a map at 512² (docs/bench.md, 2026-11-26; llvmpipe, 2 cores).
const COST_S: f64 = 7e-8;
/// A pixel shaded against one map costs about this many triangles rasterized into it: shade took
/// 5.5 ms a map for 512² pixels in the same frames (2.1e-8 s a pixel). The cost is a sum, not a
/// product: the first model (maps × triangles × pixels) said 22.7 h for a thinned frontier of
/// that scene at 512² that took 12 minutes.
const PIXEL_WEIGHT: f64 = 0.3;
/// A map texel (cleared, rasterized, read by its map's passes) costs about this many triangles:
/// `frontier --sizes 4096 --n 2` on `analytic-square` (4 triangles) at 32² took 37 ms a map for
/// 16.8 M texels (2.2e-9 s a texel; llvmpipe, 2 cores). Without it the estimate said 4 s for a
/// 12 s run there, and 39 s for a run past 120 s on a larger scene.
const TEXEL_WEIGHT: f64 = 0.031;

/// Estimated wall time of measuring `methods` on `scene`, in seconds: every configuration's fixed
/// cost plus its frames (warm-up, stages, `repeats`) at its estimated cost. The reference trace
/// (cached after its first run) is not included.
pub fn estimated_seconds(methods: &[Method], scene: &Scene, repeats: u32) -> f64 {
    let frames_each = measure::frame_count(1, repeats) as f64;
    methods
        .iter()
        .map(|m| CONFIG_S + frames_each * COST_S * estimated_cost(m, scene))
        .sum()
}

/// `s` as the largest unit that keeps it readable: `45 s`, `12 min`, `3.4 h`.
pub fn duration(s: f64) -> String {
    if s < 90.0 {
        format!("{s:.0} s")
    } else if s < 5400.0 {
        format!("{:.0} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

/// The line printed before measuring: the count, the frames and the estimate, saying what the
/// estimate rests on.
pub fn line(methods: &[Method], scene: &Scene, repeats: u32) -> String {
    line_with(
        methods,
        estimated_seconds(methods, scene, repeats),
        scene,
        repeats,
    )
}

/// [`line`] with the estimate made by the caller (the frontier sums its map sizes' groups).
pub fn line_with(methods: &[Method], seconds: f64, scene: &Scene, repeats: u32) -> String {
    let n = methods.len();
    format!(
        "{n} configuration{}, {} frames: about {} of measuring (estimated from each method's shadow maps and their texels, the scene's {} triangles and {}x{} pixels, as timed on a 2-core CPU device; a GPU is faster)",
        if n == 1 { "" } else { "s" },
        measure::frame_count(n, repeats),
        duration(seconds),
        scene.triangle_count(),
        scene.render.width,
        scene.render.height,
    )
}

/// Refuses `count` configurations over `max`; `what` names where they come from (the spec file,
/// `--methods`).
pub fn check_count(count: usize, max: usize, what: &str) -> Result<()> {
    if count <= max {
        return Ok(());
    }
    Err(Error::param(format!(
        "{what}: {count} configurations, more than --max-configs {max}; pass --max-configs {count} to run them all"
    )))
}

/// Shadow maps a method is expected to render: exact for `hard` and `regular`, a rough guess for
/// `adaptive` (it decides at run time), and the lattice's 289 for a method this file does not
/// know. It only balances shards; nothing is reported from it.
pub fn estimated_maps(method: &Method) -> f64 {
    let p = method.params_json();
    let num = |k: &str| p.get(k).and_then(|v| v.as_f64());
    match method.name() {
        "hard" => 1.0,
        "regular" => num("n").unwrap_or(17.0).powi(2),
        "adaptive" => {
            let full = (2f64.powi(num("max_level").unwrap_or(4.0) as i32) + 1.0).powi(2);
            // `p_m = inf` is stored as null: never splits, the four corners.
            match num("p_m") {
                None => 4.0,
                Some(pm) if pm < 0.0 => full,
                // Measured on the seed scenes: p_m = 0 renders about a sixth of the lattice; larger
                // thresholds split fewer quads.
                Some(pm) => 4.0 + (full - 4.0) * 0.15 / (1.0 + (1.0 + pm).log10()),
            }
        }
        // The one-map families (pcf, pcss, the filtered maps; cascades' n is its map count): they
        // were taken for 289 maps, which made `frontier --sizes 4096` say 74 s for a 15 s run.
        name if matches!(
            crate::methods::Family::of_name(name),
            crate::methods::Family::Hard
                | crate::methods::Family::Pcf
                | crate::methods::Family::Filtered
        ) =>
        {
            num("n").unwrap_or(1.0)
        }
        _ => num("n").map(|n| n * n).unwrap_or(289.0),
    }
}

/// Estimated cost of one configuration: (maps + the G-buffer pass) × (triangles + pixels weighted
/// as triangles), plus each map's texels weighted as triangles: every map rasterizes the whole
/// mesh, is cleared and written texel by texel, and is read once per pixel.
pub fn estimated_cost(method: &Method, scene: &Scene) -> f64 {
    let pixels = f64::from(scene.render.width) * f64::from(scene.render.height);
    let texels = f64::from(scene.render.shadow_map_size).powi(2);
    let maps = estimated_maps(method);
    (maps + 1.0) * (scene.triangle_count().max(1) as f64 + PIXEL_WEIGHT * pixels)
        + maps * TEXEL_WEIGHT * texels
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_and_the_limit() {
        assert_eq!(duration(45.2), "45 s");
        assert_eq!(duration(720.0), "12 min");
        assert_eq!(duration(3.4 * 3600.0), "3.4 h");
        assert!(check_count(10_000, DEFAULT_MAX_CONFIGS, "s.toml").is_ok());
        let e = check_count(10_001, DEFAULT_MAX_CONFIGS, "s.toml")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "s.toml: 10001 configurations, more than --max-configs 10000; pass --max-configs 10001 to run them all");
    }

    #[test]
    fn map_estimates() {
        let m = |s: &str| estimated_maps(&Method::parse(s, &[]).unwrap());
        assert_eq!(m("hard"), 1.0);
        assert_eq!(m("regular:n=5"), 25.0);
        assert_eq!(m("adaptive:p_m=-1"), 289.0);
        assert_eq!(m("adaptive:p_m=inf"), 4.0);
        assert!(m("adaptive:p_m=0") > m("adaptive:p_m=100"));
        assert_eq!(m("adaptive:p_m=-1,max_level=2"), 25.0);
        assert_eq!(m("pcss"), 1.0);
        assert_eq!(m("msm"), 1.0);
    }

    #[test]
    fn frame_estimates_follow_the_measured_frames() {
        // `regular:n=17` on `default` (59k triangles) at 128² took 1.8 s a frame (llvmpipe, the
        // fixed-function raster); the estimate is a frame's cost at that rate, within 1.5× of it.
        let scene = Scene::load("default", &[("resolution".into(), "128".into())]).unwrap();
        let frame = COST_S * estimated_cost(&Method::parse("regular:n=17", &[]).unwrap(), &scene);
        assert!(
            (1.8 / 1.5..=1.8 * 1.5).contains(&frame),
            "{frame} s a frame"
        );
        // A map's texels: `regular:n=2` on `analytic-square` (4 triangles) at 32² with 4096² maps
        // took 147 ms a frame (llvmpipe, 2 cores, the frontier's own timing), within 1.5× of it.
        let big_maps = Scene::load(
            "analytic-square",
            &[
                ("resolution".into(), "32".into()),
                ("shadow_map_size".into(), "4096".into()),
            ],
        )
        .unwrap();
        let frame_4096 =
            COST_S * estimated_cost(&Method::parse("regular:n=2", &[]).unwrap(), &big_maps);
        assert!(
            (0.147 / 1.5..=0.147 * 1.5).contains(&frame_4096),
            "{frame_4096} s a frame at 4096² maps"
        );
        // Four times the pixels add a fraction, not four times the frame: the mesh's raster stays.
        let big = Scene::load("default", &[("resolution".into(), "256".into())]).unwrap();
        let ratio =
            estimated_cost(&Method::parse("regular:n=17", &[]).unwrap(), &big) / (frame / COST_S);
        assert!(ratio > 1.1 && ratio < 1.5, "{ratio}");
    }
}
