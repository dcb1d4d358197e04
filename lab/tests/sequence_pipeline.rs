//! `penumbra sequence` and `penumbra failures` end to end on tiny images: per-frame rows with their
//! temporal figures, summaries, charts, APNG animations, a self-contained report, the gallery's
//! sentences, and bad flags refused before anything is written.

#[macro_use]
mod common;
use common::temp_dir;
use std::path::Path;
use std::process::{Command, Output};

const SCENE: &str = concat!(
    "name = \"tiny-seq\"\n",
    tiny_scene_head!(),
    r#"
[[mesh]]
builtin = "plane"
scale = [10.0, 1.0, 10.0]

[[mesh]]
builtin = "box"
translate = [0.0, 1.5, 0.0]
scale = [1.5, 0.2, 1.5]
"#
);

/// The binary with its own reference cache, so tests neither read nor fill the user's.
fn penumbra(cache: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(args)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .env("PENUMBRA_CACHE", cache)
        .output()
        .expect("run penumbra binary")
}

fn ok(out: Output, args: &[&str]) -> String {
    assert!(
        out.status.success(),
        "penumbra {args:?} failed: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn rows(dir: &Path) -> Vec<serde_json::Value> {
    let text = std::fs::read_to_string(dir.join("frames.jsonl")).unwrap();
    text.lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// No URL, script file, link or import; at most one script, the comparison viewer's, inline.
fn assert_self_contained(html: &str) {
    let lower = html.to_lowercase();
    for bad in [
        "http://",
        "https://",
        "<script src",
        "<link",
        "@import",
        "url(",
        "href=",
        "fetch(",
    ] {
        assert!(!lower.contains(bad), "report.html contains {bad:?}");
    }
    assert_eq!(
        lower.matches("<script").count(),
        usize::from(lower.contains("<div class=\"viewer")),
        "a script only with a viewer"
    );
    let imgs = lower.matches("<img ").count();
    assert!(imgs > 0);
    assert_eq!(
        imgs,
        lower.matches("<img src=\"data:image/").count(),
        "an <img> is not a data: URI"
    );
}

/// acTL chunk of an APNG: (frames, plays).
fn apng_frames(bytes: &[u8]) -> (u32, u32) {
    let at = bytes
        .windows(4)
        .position(|w| w == b"acTL")
        .expect("an APNG has acTL");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(at + 4), be(at + 8))
}

#[test]
fn a_four_frame_sequence_end_to_end() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let dir = temp_dir("sequence_pipeline");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let (cache, out) = (dir.join("cache"), dir.join("out"));
    let args = [
        "sequence",
        "--scene",
        scene.to_str().unwrap(),
        "--methods",
        "hard,regular:n=3,adaptive",
        "--frames",
        "4",
        "--animate",
        "light",
        "--offset",
        "3,0,0",
        "--out",
        out.to_str().unwrap(),
    ];
    let stdout = ok(penumbra(&cache, &args), &args);
    assert!(
        stdout.contains("temporal RMSE") && stdout.contains("report:"),
        "{stdout}"
    );

    let rows = rows(&out);
    assert_eq!(rows.len(), 12, "3 methods × 4 frames");
    for r in &rows {
        let frame = r["frame"].as_u64().unwrap();
        assert_eq!(r["temporal"].is_null(), frame == 0, "{r}");
        assert!(r["metrics"]["rmse"].as_f64().unwrap() > 0.0);
        assert_eq!(
            r["light_center"][0].as_f64().unwrap(),
            frame as f64,
            "the light moves 1 per frame: {r}"
        );
        if frame > 0 {
            let t = &r["temporal"];
            assert!(
                t["pixels"].as_u64().unwrap() > 0 && t["temporal_rmse"].as_f64().unwrap() > 0.0,
                "{r}"
            );
        }
    }
    let maps: Vec<u64> = rows
        .iter()
        .filter(|r| r["label"] == "regular:n=3")
        .map(|r| r["maps"].as_u64().unwrap())
        .collect();
    assert_eq!(maps, [9, 9, 9, 9]);
    // Each frame has its own reference: the hard shadow's error is not the same in every frame.
    let hard: Vec<f64> = rows
        .iter()
        .filter(|r| r["label"] == "hard")
        .map(|r| r["metrics"]["rmse"].as_f64().unwrap())
        .collect();
    assert!(hard.windows(2).any(|w| w[0] != w[1]), "{hard:?}");

    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["frames"], 4);
    assert_eq!(summary["animation"]["subject"], "light");
    let methods = summary["methods"].as_array().unwrap();
    assert_eq!(methods.len(), 3);
    for m in methods {
        // The pooled temporal figures cover the three frame pairs.
        let pairs: u64 = rows
            .iter()
            .filter(|r| r["label"] == m["label"])
            .filter_map(|r| r["temporal"]["pixels"].as_u64())
            .sum();
        assert_eq!(m["temporal"]["pixels"].as_u64().unwrap(), pairs, "{m}");
    }
    assert_eq!(
        std::fs::read_to_string(out.join("frames.csv"))
            .unwrap()
            .lines()
            .count(),
        13
    );
    for chart in [
        "error_per_frame",
        "popping_per_frame",
        "temporal_error_per_frame",
        "maps_per_frame",
    ] {
        for ext in ["svg", "png"] {
            assert!(
                out.join(format!("charts/{chart}.{ext}")).is_file(),
                "missing {chart}.{ext}"
            );
        }
    }
    for anim in ["reference", "hard", "regular_n_3", "adaptive_p_m_0"] {
        let bytes = std::fs::read(out.join(format!("animations/{anim}.png"))).unwrap();
        assert_eq!(apng_frames(&bytes), (4, 0), "{anim}");
    }
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert_self_contained(&html);
    assert_eq!(
        html.matches("data:image/png").count(),
        4,
        "one animation per method and the reference"
    );
    assert!(html.contains("Popping per frame") && html.contains("temporal RMSE"));
}

/// `--reuse both`: every method runs without and with reuse in each frame, its V equal bit for
/// bit; on a camera path the regular grid keeps all its maps after the first frame, and the
/// report charts frame time and maps rendered per frame.
#[test]
fn reuse_both_runs_each_method_twice_with_equal_v() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let dir = temp_dir("sequence_reuse");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let (cache, out) = (dir.join("cache"), dir.join("out"));
    let args = [
        "sequence",
        "--scene",
        scene.to_str().unwrap(),
        "--methods",
        "regular:n=3,adaptive",
        "--frames",
        "3",
        "--animate",
        "camera",
        "--reuse",
        "both",
        "--reference",
        "continuous",
        "--samples",
        "2",
        "--out",
        out.to_str().unwrap(),
    ];
    let stdout = ok(penumbra(&cache, &args), &args);
    assert!(stdout.contains("V equal"), "{stdout}");
    let rows = rows(&out);
    assert_eq!(rows.len(), 12, "2 methods × 2 runs × 3 frames");
    for r in rows.iter().filter(|r| r["reuse"] == true) {
        assert_eq!(r["v_equal_without_reuse"], true, "{r}");
    }
    for r in rows
        .iter()
        .filter(|r| r["label"] == "regular:n=3 (reuse on)")
    {
        let (rendered, kept) = (
            r["reuse_counts"]["rendered"].as_u64().unwrap(),
            r["reuse_counts"]["kept"].as_u64().unwrap(),
        );
        assert_eq!(
            (rendered, kept),
            if r["frame"] == 0 { (9, 0) } else { (0, 9) },
            "{r}"
        );
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["reuse"], "both");
    let on = summary["methods"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["label"] == "regular:n=3 (reuse on)")
        .unwrap();
    assert_eq!(on["v_equal_frames"], serde_json::json!([3, 3]));
    assert!(
        on["time_ratio_to_without_reuse"].as_f64().unwrap() > 0.0,
        "{on}"
    );
    assert_eq!(on["kept_mean_after_first"], 9.0);
    for chart in ["frame_time_per_frame", "maps_rendered_per_frame"] {
        assert!(
            out.join(format!("charts/{chart}.svg")).is_file(),
            "missing {chart}"
        );
    }
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(
        html.contains("Shadow maps rasterized whole per frame")
            && html.contains("Frame time per frame")
            && html.contains("V equal without reuse")
    );
    let bad = penumbra(
        &cache,
        &[
            "sequence",
            "--reuse",
            "sometimes",
            "--out",
            dir.join("bad").to_str().unwrap(),
        ],
    );
    assert_eq!(bad.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&bad.stderr).trim(),
        "error: --reuse sometimes: use on, off or both"
    );
    assert!(!dir.join("bad").exists());
}

/// `--timing stages`: every row of `frames.jsonl` holds each stage's wall clock and the
/// renderer's attach (a moved mesh, so the kept maps draw their rectangles again).
#[test]
fn timing_stages_writes_each_stage_per_row() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let dir = temp_dir("sequence_stages");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let (cache, out) = (dir.join("cache"), dir.join("out"));
    let args = [
        "sequence",
        "--scene",
        scene.to_str().unwrap(),
        "--methods",
        "regular:n=3",
        "--frames",
        "2",
        "--animate",
        "occluder",
        "--timing",
        "stages",
        "--samples",
        "2",
        "--out",
        out.to_str().unwrap(),
    ];
    ok(penumbra(&cache, &args), &args);
    let rows = rows(&out);
    assert_eq!(rows.len(), 2);
    for r in &rows {
        let stages = r["stages_ms"].as_object().expect("stages_ms");
        for key in ["gbuffer", "shadow_raster", "shade", "readback", "attach"] {
            let ms = stages.get(key).and_then(|v| v.as_f64());
            assert!(ms.is_some_and(|ms| ms >= 0.0), "{key}: {r}");
        }
        // The stages are inside the frame's clock.
        let inside: f64 = ["gbuffer", "shadow_raster", "shade", "readback"]
            .iter()
            .map(|k| stages[*k].as_f64().unwrap())
            .sum();
        assert!(inside <= r["frame_ms"].as_f64().unwrap() + 1.0, "{r}");
    }
    // The second frame's maps are each rendered, kept or redrawn in part (the moved box).
    let m = &rows[1]["reuse_counts"];
    let n = |k: &str| m[k].as_u64().unwrap();
    assert_eq!(n("rendered") + n("kept") + n("redrawn"), 9, "{m}");
    assert_eq!(n("evicted"), 0, "{m}");
    let bad = penumbra(
        &cache,
        &[
            "sequence",
            "--timing",
            "fast",
            "--out",
            dir.join("bad").to_str().unwrap(),
        ],
    );
    assert_eq!(bad.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&bad.stderr).trim(),
        "error: --timing fast: use frame or stages"
    );
    assert!(!dir.join("bad").exists());
}

#[test]
fn a_still_sequence_has_no_temporal_error() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let dir = temp_dir("sequence_still");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let (cache, out) = (dir.join("cache"), dir.join("out"));
    let args = [
        "sequence",
        "--scene",
        scene.to_str().unwrap(),
        "--methods",
        "regular:n=3,adaptive",
        "--frames",
        "3",
        "--animate",
        "occluder",
        "--offset",
        "0,0,0",
        "--out",
        out.to_str().unwrap(),
    ];
    ok(penumbra(&cache, &args), &args);
    for r in rows(&out).iter().filter(|r| r["frame"] != 0) {
        assert_eq!(r["temporal"]["temporal_rmse"], 0.0, "{r}");
        assert_eq!(r["temporal"]["popping_pixels"], 0, "{r}");
    }
}

#[test]
fn bad_sequence_flags_are_one_line_and_write_nothing() {
    let dir = temp_dir("sequence_bad");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    for (args, message) in [
        (
            vec!["--frames", "1"],
            "error: --frames 1: a sequence needs 2..=1000 frames",
        ),
        (
            vec!["--animate", "sun"],
            "error: --animate sun: use light, camera or occluder",
        ),
        (
            vec!["--animate", "camera", "--path", "circle"],
            "error: --path circle: --animate camera moves along orbit or segment",
        ),
        (
            vec!["--offset", "1,x,2"],
            "error: --offset 1,x,2: expected three finite numbers x,y,z",
        ),
        (
            vec!["--animate", "occluder", "--mesh", "9"],
            "error: --mesh 9: builtin:default has meshes 1..=2",
        ),
        (
            vec!["--methods", "hard,blur"],
            "error: unknown method `blur`",
        ),
    ] {
        let mut all = vec!["sequence", "--out", o];
        all.extend(args.iter().copied());
        let r = penumbra(&dir.join("cache"), &all);
        assert_eq!(r.status.code(), Some(1), "{all:?}");
        let stderr = String::from_utf8_lossy(&r.stderr);
        // One line, starting with the whole message (the list of known methods grows).
        assert_eq!(stderr.lines().count(), 1, "{all:?}: {stderr}");
        assert!(stderr.starts_with(message), "{all:?}: {stderr}");
        assert!(!out.exists(), "{all:?} wrote output");
    }
}

/// A moved light goes through the scene file's light checks in every frame, before any frame is
/// traced or rendered; a sun, which has no position, is not moved at all.
#[test]
fn moved_lights_are_checked_before_any_frame() {
    let dir = temp_dir("sequence_lights");
    let out = dir.join("out");
    let disk = dir.join("disk.toml");
    let head = tiny_scene_head!().replace(
        "center = [0.0, 8.0, 0.0]\nedge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 2.0]",
        "kind = \"disk\"\ncenter = [0.0, 8.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\nradius = 1.0",
    );
    std::fs::write(
        &disk,
        format!("{head}[[mesh]]\nbuiltin = \"plane\"\nscale = 10.0\n"),
    )
    .unwrap();
    let d = disk.display();
    for (args, message) in [
        (
            vec!["--scene", "sun-edge"],
            "error: --animate light: builtin:sun-edge's light is a sun (kind = \"sun\"), which has a direction but no position, so moving it changes nothing; animate the camera (--animate camera) or a mesh (--animate occluder)".to_string(),
        ),
        // The disk ends 2 below the ground, facing down: the file would be refused the same way.
        (
            vec!["--scene", disk.to_str().unwrap(), "--frames", "3", "--offset", "0,-10,0"],
            format!("error: --animate: frame 3 of 3 (light along a segment by (0, -10, 0), the light's centre at [0.0, -2.0, 0.0]): {d}: light: the disk emits along light.normal = [0.0, -1.0, 0.0], away from every mesh: nothing would be lit; turn it towards the meshes"),
        ),
        // Halfway, the sphere (radius 1.5) reaches into the ground.
        (
            vec!["--scene", "point-edge", "--frames", "3", "--offset", "0,-10,0"],
            "error: --animate: frame 2 of 3 (light along a segment by (0, -10, 0), the light's centre at [1.0, 1.0, 0.5]): builtin:point-edge: light.position = [1.0, 1.0, 0.5], light.radius = 1.5: the emitter's sphere reaches into mesh 1 (a triangle of it is 1 from the centre)".to_string(),
        ),
    ] {
        let mut all = vec!["sequence", "--methods", "hard", "--out", out.to_str().unwrap()];
        all.extend(args.iter().copied());
        let r = penumbra(&dir.join("cache"), &all);
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{all:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{all:?}: {stderr}");
        assert!(stderr.starts_with(&message), "{all:?}:\n{stderr}\n{message}");
        assert!(!out.exists() && !dir.join("cache").exists(), "{all:?} wrote output or traced a reference");
    }
}

#[test]
fn the_failure_gallery_states_each_failure_from_its_figures() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    let dir = temp_dir("failures_gallery");
    let (cache, out) = (dir.join("cache"), dir.join("out"));
    let args = [
        "failures",
        "--resolution",
        "48",
        "--frames",
        "3",
        "--methods",
        "hard,regular:n=9,adaptive",
        "--out",
        out.to_str().unwrap(),
    ];
    ok(penumbra(&cache, &args), &args);
    let gallery: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("gallery.json")).unwrap()).unwrap();
    let scenes = gallery["scenes"].as_array().unwrap();
    let names: Vec<&str> = scenes.iter().map(|s| s["name"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        [
            "pole-between-corners",
            "overlapping-occluders",
            "grazing-ground"
        ]
    );
    // The blind spot: adaptive keeps its 4 corner maps and sees the light unblocked under the pole.
    let pole = &scenes[0];
    let adaptive = pole["figures"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["method"] == "adaptive")
        .unwrap();
    assert_eq!(adaptive["shadow_maps"], 4, "{adaptive}");
    assert!(
        adaptive["bright"].as_u64().unwrap() > 0 && adaptive["bright_v"].as_f64().unwrap() > 0.99,
        "{adaptive}"
    );
    let expect = format!(
        "adaptive:p_m=0 misses the pole: V = {:.2} where the reference is {:.2} in {} pixels",
        adaptive["bright_v"].as_f64().unwrap(),
        adaptive["bright_ref"].as_f64().unwrap(),
        adaptive["bright"]
    );
    assert!(
        pole["sentence"].as_str().unwrap().starts_with(&expect),
        "{} vs {expect}",
        pole["sentence"]
    );
    for s in scenes {
        let name = s["name"].as_str().unwrap();
        assert!(out.join(format!("{name}/reference.png")).is_file());
        for slug in ["hard", "regular_n_9", "adaptive_p_m_0"] {
            assert!(
                out.join(format!("{name}/{slug}_signed_error.png"))
                    .is_file(),
                "{name}/{slug}"
            );
        }
    }
    // The popping sequence keeps the adaptive methods and the densest grid.
    let labels: Vec<String> = rows(&out.join("popping-sequence"))
        .iter()
        .map(|r| r["label"].as_str().unwrap().to_string())
        .collect();
    assert_eq!(labels.len(), 6);
    assert!(!labels.iter().any(|l| l == "hard"), "{labels:?}");
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert_self_contained(&html);
    for s in scenes {
        // As minijinja escapes text: `'` and `/` become character references.
        let escaped = s["sentence"]
            .as_str()
            .unwrap()
            .replace('\'', "&#x27;")
            .replace('/', "&#x2f;");
        assert!(html.contains(&escaped), "report lacks {}", s["sentence"]);
    }
    assert!(
        html.contains("Failure gallery")
            && html.contains("Temporal sequence: pole-between-corners")
    );
    // One viewer per failure scene: its reference, then each method's signed error map.
    assert_eq!(
        html.matches("<div class=\"viewer compact\"").count(),
        scenes.len()
    );
    assert_eq!(
        html.matches("<div class=\"v-item\" data-label=\"reference\" data-reference>")
            .count(),
        scenes.len()
    );
}
