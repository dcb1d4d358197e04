//! GPU tests for this issue's scenes and suite: the blind-spot scene does what its comments say,
//! and `penumbra bench --suite seed-table2` writes its two files (on small stand-in scenes).
//! Without an adapter these fail with the install hint; they never skip.

#[macro_use]
mod common;
use common::{gpu, penumbra, temp_dir};
use penumbra::research::frame;
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;
use penumbra_lab::studies::bench::fair::grid_n;
use std::path::Path;

fn scene_file(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("scenes")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

#[test]
fn pole_between_corners_is_missed_by_adaptive_and_seen_by_regular() {
    let ctx = gpu();
    let small = [("resolution".to_string(), "128".to_string())];
    let scene = Scene::load(&scene_file("pole-between-corners.toml"), &small).unwrap();
    let adaptive = frame::render(
        ctx,
        &scene,
        &Method::parse("adaptive:p_m=0", &[]).unwrap(),
        TimingMode::Frame,
    )
    .unwrap();
    let regular = frame::render(
        ctx,
        &scene,
        &Method::parse("regular", &[]).unwrap(),
        TimingMode::Frame,
    )
    .unwrap();
    let geometry: Vec<usize> = (0..adaptive.visibility.len())
        .filter(|&i| adaptive.gbuffer.is_geometry(i))
        .collect();
    assert!(geometry.len() > 1000, "the scene is not in view");
    // Every corner of the level-0 quad sees every pixel lit: 4 maps, nothing split, V = 1.
    assert_eq!(adaptive.output.shadow_maps, 4);
    assert!(geometry.iter().all(|&i| adaptive.visibility[i] == 1.0));
    // The 17x17 lattice sees the pole: 40% of the light blocked under its middle (V = 0.6 for the
    // continuous light; the lattice's 7 of 17 columns give 10/17 = 0.588).
    let min = geometry
        .iter()
        .map(|&i| regular.visibility[i])
        .fold(1.0f32, f32::min);
    assert!((0.55..0.65).contains(&min), "regular min V = {min}");
}

const STAND_IN: &str = concat!(
    "triangles = 14\n",
    tiny_scene_head!(),
    r#"
[[mesh]]
builtin = "plane"
scale = 10.0

[[mesh]]
builtin = "box"
translate = [0.0, 1.0, 0.0]
"#
);

#[test]
fn seed_table2_suite_writes_table_and_jsonl() {
    let dir = temp_dir("bench_suite");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    for name in ["bunny", "bunny-seed-framing", "grove", "cows", "teapot"] {
        std::fs::write(scenes.join(format!("{name}.toml")), STAND_IN).unwrap();
    }
    let out = dir.join("out");
    let cache = dir.join("cache");
    let run = common::penumbra_env(
        // `--set` goes over every scene file: the compute raster here, named under the table.
        &[
            "bench",
            "--suite",
            "seed-table2",
            "--repeats",
            "2",
            "--scenes",
            scenes.to_str().unwrap(),
            "--set",
            "raster=compute",
            "--out",
            out.to_str().unwrap(),
        ],
        &[("PENUMBRA_CACHE", cache.to_str().unwrap())],
    );
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        run.status.success(),
        "bench failed (a GPU test: it needs an adapter): {stderr}"
    );
    let table = std::fs::read_to_string(out.join("table2.md")).unwrap();
    let adapter = gpu().summary.name.clone();
    assert!(
        table.contains(&format!("Adapter: **{adapter}**")),
        "{table}"
    );
    for (scene, seed) in [
        ("bunny 兔子", "19.89 (45) | 1.73 (289) | 11.5x"),
        ("grove", "0.9x"),
        ("cows", "4.8x"),
        ("teapot", "3.2x"),
    ] {
        let row = table
            .lines()
            .find(|l| l.starts_with(&format!("| {scene}")))
            .unwrap_or_else(|| panic!("no row {scene}: {table}"));
        assert!(row.contains(seed), "{row}");
        assert!(row.contains("(289)"), "regular uses 289 maps: {row}");
    }
    assert!(
        table.contains("NOT the seed's 512x512"),
        "stand-in settings must be flagged: {table}"
    );
    // Error columns: RMSE / FLIP of each method against the continuous reference.
    for scene in ["bunny", "grove", "cows", "teapot"] {
        let row = table
            .lines()
            .find(|l| l.starts_with(&format!("| {scene}")))
            .unwrap();
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        for cell in &cells[6..8] {
            let (rmse, flip) = cell
                .split_once(" / ")
                .unwrap_or_else(|| panic!("no RMSE / FLIP in {row}"));
            let (rmse, flip): (f64, f64) = (rmse.parse().unwrap(), flip.parse().unwrap());
            assert!(
                rmse > 0.0 && rmse < 0.2 && (0.0..0.2).contains(&flip),
                "{row}"
            );
        }
    }
    assert!(table.contains("continuous 32x32"), "{table}");
    assert!(
        table.contains(", with `--set raster=compute`. Per-stage times"),
        "{table}"
    );
    let html =
        std::fs::read_to_string(out.join("report.html")).expect("the suite writes report.html");
    assert!(
        html.contains("<svg") || html.contains("data:image/svg+xml"),
        "the report has charts"
    );
    assert!(
        !html.contains("src=\"http") && !html.contains("<script src"),
        "self-contained"
    );
    // One schema with compare: the record layer's rows, provenance included.
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(out.join("results.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(
        lines.len(),
        20,
        "adaptive, lattice, fair grid and per region, per scene"
    );
    for l in &lines {
        assert_eq!(l["frame_ms_runs"].as_array().unwrap().len(), 2, "{l}");
        let (rmse, flip) = (
            l["metrics"]["rmse"].as_f64().unwrap(),
            l["metrics"]["flip_mean"].as_f64().unwrap(),
        );
        assert!(rmse.is_finite() && flip.is_finite(), "{l}");
        assert_eq!(l["provenance"]["command"], "bench seed-table2");
        assert_eq!(l["provenance"]["scene_sha256"].as_str().unwrap().len(), 64);
        assert_eq!(l["reference"], "continuous 32x32, CPU BVH");
        assert!(
            l["stages_ms"].as_object().unwrap().contains_key("shade"),
            "{l}"
        );
        assert_eq!(
            l["raster"], "compute",
            "--set raster=compute reaches every scene"
        );
    }
    assert_eq!(lines[1]["method"], "regular");
    assert_eq!(lines[1]["maps"], 289);
    check_fair_rows(&table, &lines);

    // One report from a compare output and the bench output together.
    let compare_out = dir.join("compare");
    let stand_in = scenes.join("teapot.toml");
    let run = common::penumbra_env(
        &[
            "compare",
            "--scene",
            stand_in.to_str().unwrap(),
            "--methods",
            "hard,regular:n=3",
            "--repeats",
            "1",
            "--out",
            compare_out.to_str().unwrap(),
        ],
        &[("PENUMBRA_CACHE", cache.to_str().unwrap())],
    );
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let both = dir.join("both");
    let run = penumbra(&[
        "report",
        compare_out.join("results.jsonl").to_str().unwrap(),
        out.join("results.jsonl").to_str().unwrap(),
        "--out",
        both.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let md = std::fs::read_to_string(both.join("report.md")).unwrap();
    assert!(
        md.contains("regular:n=3")
            && md.contains("adaptive:p_m=0")
            && md.contains("| produced by | compare; bench seed-table2 |"),
        "{md}"
    );
    assert!(
        md.contains("| rows | 22 |"),
        "2 compare rows and 20 bench rows: {md}"
    );
}

/// Per scene: the third row is the centred grid with N² the square nearest to the adaptive row's
/// maps, and the fair-rows table gives both comparisons the verdict their measured figures imply.
fn check_fair_rows(table: &str, lines: &[serde_json::Value]) {
    let scenes = ["bunny", "bunny-seed-framing", "grove", "cows", "teapot"];
    for (scene, rows) in scenes.iter().zip(lines.chunks(4)) {
        let [adaptive, lattice, fair, regions] = rows else {
            panic!("four rows per scene: {rows:?}")
        };
        for r in rows {
            assert_eq!(r["scene"], *scene, "{r}");
        }
        let maps = adaptive["maps"].as_u64().unwrap() as u32;
        let n = grid_n(maps);
        // The rule in full: no other N ≥ 2 puts N² nearer to the adaptive count.
        let dist = |k: u32| (i64::from(k * k) - i64::from(maps)).abs();
        assert!((2..40).all(|k| dist(k) >= dist(n)), "{maps} maps: n = {n}");
        assert_eq!(
            fair["label"],
            format!("regular:n={n},layout=centred"),
            "{fair}"
        );
        assert_eq!(fair["maps"].as_u64().unwrap(), u64::from(n * n), "{fair}");
        for grid in [lattice, fair] {
            let label = grid["label"].as_str().unwrap();
            let line = table
                .lines()
                .find(|l| l.starts_with(&format!("| {scene} | `{label}` |")))
                .unwrap_or_else(|| panic!("no fair-rows line for {scene} {label}: {table}"));
            let (a_ms, g_ms) = (
                adaptive["frame_ms"].as_f64().unwrap(),
                grid["frame_ms"].as_f64().unwrap(),
            );
            let (a_rmse, g_rmse) = (
                adaptive["metrics"]["rmse"].as_f64().unwrap(),
                grid["metrics"]["rmse"].as_f64().unwrap(),
            );
            let expected = if a_ms <= g_ms && a_rmse <= g_rmse {
                "adaptive dominates".to_string()
            } else if a_ms > g_ms && a_rmse >= g_rmse {
                "grid dominates".to_string()
            } else {
                format!(
                    "trade-off: adaptive {:.2}× faster at {:.2}× the RMSE",
                    g_ms / a_ms,
                    a_rmse / g_rmse
                )
            };
            assert!(
                line.ends_with(&format!("| {expected} |")),
                "expected `{expected}`: {line}"
            );
            assert!(
                line.contains(&format!("| {:.2}x |", g_ms / a_ms)),
                "speed-up of {scene} {label}: {line}"
            );
        }
        check_region_row(table, scene, regions, lattice, fair);
    }
}

/// The per-region row: its speed-ups over both grids are the medians' ratios, and each verdict is
/// the one the measured figures imply.
fn check_region_row(
    table: &str,
    scene: &str,
    regions: &serde_json::Value,
    lattice: &serde_json::Value,
    fair: &serde_json::Value,
) {
    assert_eq!(regions["method"], "regions", "{regions}");
    let line = table
        .lines()
        .skip_while(|l| !l.starts_with("## Per region: `regions`"))
        .find(|l| l.starts_with(&format!("| {scene} |")))
        .unwrap_or_else(|| panic!("no per-region line for {scene}: {table}"));
    let cells: Vec<&str> = line.split('|').map(str::trim).collect();
    let (r_ms, r_rmse) = (
        regions["frame_ms"].as_f64().unwrap(),
        regions["metrics"]["rmse"].as_f64().unwrap(),
    );
    assert_eq!(cells[2], regions["maps"].to_string(), "{line}");
    assert_eq!(cells[4], format!("{r_rmse:.5}"), "{line}");
    assert_eq!(
        cells[8],
        format!("`{}`", fair["label"].as_str().unwrap()),
        "{line}"
    );
    for (grid, speed, verdict) in [(lattice, 5, 7), (fair, 9, 11)] {
        let (g_ms, g_rmse) = (
            grid["frame_ms"].as_f64().unwrap(),
            grid["metrics"]["rmse"].as_f64().unwrap(),
        );
        assert_eq!(cells[speed], format!("{:.2}x", g_ms / r_ms), "{line}");
        let expected = if r_ms <= g_ms && r_rmse <= g_rmse {
            "per region dominates".to_string()
        } else if r_ms > g_ms && r_rmse >= g_rmse {
            "grid dominates".to_string()
        } else {
            format!(
                "trade-off: per region {:.2}× faster at {:.2}× the RMSE",
                g_ms / r_ms,
                r_rmse / g_rmse
            )
        };
        assert_eq!(cells[verdict], expected, "{line}");
    }
}

#[test]
fn fair_grid_is_the_nearest_square_of_at_least_four() {
    // 1 and 2 sit nearest 1², floored to 2x2; 45 is 4 from 49 and 9 from 36; 111 is 10 from 121, 11 from 100.
    for (maps, n) in [
        (1, 2),
        (2, 2),
        (6, 2),
        (7, 3),
        (35, 6),
        (36, 6),
        (42, 6),
        (43, 7),
        (45, 7),
        (62, 8),
        (85, 9),
        (111, 11),
        (289, 17),
    ] {
        assert_eq!(grid_n(maps), n, "{maps} maps");
    }
}

#[test]
fn bench_input_errors_are_one_line_and_write_nothing() {
    let dir = temp_dir("bench_errors");
    let out = dir.join("out");
    for (args, expected) in [
        (vec!["--only", "horse"], "error: bench: `horse` is not a seed-table2 scene (known: bunny, bunny-seed-framing, grove, cows, teapot)"),
        (vec!["--scenes", "/nonexistent-scenes"], "error: /nonexistent-scenes/bunny.toml: no such scene file"),
        (vec!["--repeats", "0"], "error: bench: --repeats must be at least 1"),
        (vec!["--set", "raster=sideways"], "error: --set raster=sideways: unknown variant `sideways`"),
        (vec!["--set", "nonsense=1"], "error: scenes/bunny.toml: --set nonsense: unknown render setting"),
    ] {
        let mut all = vec!["bench", "--suite", "seed-table2", "--out", out.to_str().unwrap()];
        all.extend(args);
        let run = penumbra(&all);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.starts_with(expected), "{stderr}");
        assert!(!out.exists());
    }
}

/// `bench --reuse on`: every frame after the warm-up keeps the maps of the still scene, and each
/// frame's line says so; `--reuse` takes on or off.
#[test]
fn bench_with_reuse_keeps_every_map_after_the_warm_up() {
    let dir = temp_dir("bench_reuse");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::write(scenes.join("cows.toml"), STAND_IN).unwrap();
    let (out, cache) = (dir.join("out"), dir.join("cache"));
    let args = [
        "bench",
        "--suite",
        "seed-table2",
        "--repeats",
        "1",
        "--only",
        "cows",
        "--regions",
        "none",
        "--scenes",
        scenes.to_str().unwrap(),
        "--reuse",
        "on",
        "--out",
        out.to_str().unwrap(),
    ];
    let run = common::penumbra_env(&args, &[("PENUMBRA_CACHE", cache.to_str().unwrap())]);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "bench failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let lines: Vec<&str> = stdout
        .lines()
        .filter(|l| l.contains("regular:n=17"))
        .collect();
    assert!(
        lines
            .iter()
            .any(|l| l.contains("warm-up") && l.contains("289 maps (289 rendered, 0 kept)")),
        "{stdout}"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.contains("1/1") && l.contains("289 maps (0 rendered, 289 kept)")),
        "{stdout}"
    );
    let bad = common::penumbra(&[
        "bench",
        "--suite",
        "seed-table2",
        "--reuse",
        "maybe",
        "--out",
        dir.join("bad").to_str().unwrap(),
    ]);
    assert!(!bad.status.success(), "--reuse maybe is refused");
    assert!(
        String::from_utf8_lossy(&bad.stderr).contains("--reuse"),
        "{}",
        String::from_utf8_lossy(&bad.stderr)
    );
}
