//! Issue 26's absurd values and messages: each refused case exits 1 with exactly one line naming the
//! key and the value, and writes nothing; `--set` takes render settings only, in every command, so
//! `--set cull=none` works where the docs say it does.

#[macro_use]
mod common;
use common::SWEEP_SCENE as SCENE;
use std::path::{Path, PathBuf};
use std::process::Output;

/// A box shut around the light over a plane: the reference is dark everywhere.
const ENCLOSED: &str = concat!(
    "name = \"enclosed\"\n",
    r#"
[camera]
eye = [0.0, 6.0, 8.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 45.0

[light]
center = [0.0, 2.0, 0.0]
edge_u = [0.5, 0.0, 0.0]
edge_v = [0.0, 0.0, 0.5]

[render]
width = 32
height = 32
shadow_map_size = 64

[[mesh]]
builtin = "plane"
scale = 10.0

[[mesh]]
builtin = "box"
translate = [0.0, 2.0, 0.0]
scale = 2.0
"#
);

/// Runs the binary in `dir` (relative paths: `scene.toml`, `out`).
fn run_in(dir: &Path, args: &[&str]) -> Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .current_dir(dir)
        .args(args)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .unwrap()
}

/// A folder holding `scene.toml` with `scene` in it.
fn folder(case: &str, scene: &str) -> PathBuf {
    let dir = common::temp_dir(&format!("absurd_{case}"));
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    dir
}

/// `args` with `scene` must fail with exit 1 and exactly `want` on stderr; nothing is written
/// (no `out`, nothing on stdout) and nothing is lost (the scene file is as it was).
fn refused(case: &str, scene: &str, args: &[&str], want: &str) {
    let dir = folder(case, scene);
    let out = run_in(&dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{case}: {stderr}");
    assert_eq!(
        stderr.lines().collect::<Vec<_>>(),
        [format!("error: {want}")],
        "{case}"
    );
    assert!(
        out.stdout.is_empty(),
        "{case}: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert!(!dir.join("out").exists(), "{case}: wrote an output folder");
    assert_eq!(
        std::fs::read_to_string(dir.join("scene.toml")).unwrap(),
        scene,
        "{case}: the scene file changed"
    );
    let entries: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(entries, ["scene.toml"], "{case}: left files behind");
}

fn render(extra: &[&'static str]) -> Vec<&'static str> {
    [
        &[
            "render",
            "--scene",
            "scene.toml",
            "--method",
            "hard",
            "--out",
            "out",
        ],
        extra,
    ]
    .concat()
}

/// SCENE with one line replaced (which must be there).
fn with(from: &str, to: &str) -> String {
    assert!(SCENE.contains(from), "{from}");
    SCENE.replacen(from, to, 1)
}

#[test]
fn render_settings_out_of_bounds_name_the_key_and_value() {
    refused(
        "map1",
        SCENE,
        &render(&["--set", "shadow_map_size=1"]),
        "scene.toml: render.shadow_map_size = 1: must be at least 16",
    );
    refused(
        "map3",
        &with("shadow_map_size = 64", "shadow_map_size = 3"),
        &render(&[]),
        "scene.toml: render.shadow_map_size = 3: must be at least 16",
    );
    refused(
        "hybrid8",
        SCENE,
        &render(&["--set", "maps=hybrid", "--set", "base=8"]),
        "scene.toml: render.hybrid.base = 8: must be at least 16",
    );
    refused(
        "bias",
        SCENE,
        &render(&["--set", "bias.constant=-1"]),
        "scene.toml: render.bias.constant = -1: must be >= 0 (a negative bias shadows every surface with itself)",
    );
    refused(
        "offset",
        SCENE,
        &render(&["--set", "render.bias.normal_offset=-0.5"]),
        "scene.toml: render.bias.normal_offset = -0.5: must be >= 0 (a negative bias shadows every surface with itself)",
    );
}

#[test]
fn mesh_values_out_of_bounds_name_the_mesh_key_and_value() {
    let box_at = "translate = [0.0, 1.0, 0.0]";
    let cases = [
        ("albedo", format!("{box_at}\nalbedo = [1.5, 0.5, -0.1]"), "mesh 2 albedo = [1.5, 0.5, -0.1]: each component must be in [0, 1]"),
        ("far", "translate = [3e38, 1.0, 0.0]".to_string(), "mesh 2: translate = [3e38, 1.0, 0.0]: each component must be within ±1e6 (f32 has no precision left beyond)"),
        ("nan", "translate = [nan, 1.0, 0.0]".to_string(), "mesh 2: translate = [NaN, 1.0, 0.0]: has a NaN or infinite number"),
        ("inf_scale", format!("{box_at}\nscale = [1.0, inf, 1.0]"), "mesh 2: scale = [1.0, inf, 1.0]: has a NaN or infinite number"),
        ("tiny", format!("{box_at}\nscale = 1e-30"), "mesh 2: scale = 1e-30: each factor's size must be within [1e-6, 1e6]"),
        ("zero", format!("{box_at}\nscale = [1.0, 0.0, 1.0]"), "mesh 2: scale = [1.0, 0.0, 1.0]: each factor's size must be within [1e-6, 1e6]"),
        ("spin", format!("{box_at}\nrotate_deg = [0.0, 1e9, 0.0]"), "mesh 2: rotate_deg = [0.0, 1000000000.0, 0.0]: each angle must be within ±3600 degrees"),
        (
            "placed",
            "translate = [9e5, 1.0, 0.0]\nscale = 1e6".to_string(),
            "mesh 2: a placed vertex lands at [1400000.0, -499999.0, -500000.0], beyond ±1e6: shrink translate, scale or the instances",
        ),
    ];
    for (case, line, want) in cases {
        refused(
            case,
            &with(box_at, &line),
            &render(&[]),
            &format!("scene.toml: {want}"),
        );
    }
}

#[test]
fn camera_values_get_their_own_messages() {
    let cases = [
        (
            "fov",
            ("fov_y_deg = 45.0", "fov_y_deg = 179.99"),
            "camera.fov_y_deg = 179.99: must be in [0.01, 179] degrees (near 180 the whole scene shrinks to a point; 180 has no projection)",
        ),
        ("up0", ("fov_y_deg = 45.0", "fov_y_deg = 45.0\nup = [0.0, 0.0, 0.0]"), "camera.up = [0.0, 0.0, 0.0]: has no direction; give the way up on screen, e.g. [0.0, 1.0, 0.0]"),
        (
            "up_parallel",
            ("fov_y_deg = 45.0", "fov_y_deg = 45.0\nup = [0.0, -3.0, -4.0]"),
            "camera.up = [0.0, -3.0, -4.0] is parallel to the view direction (camera.target − camera.eye = [0.0, -6.0, -8.0]): give an up across it",
        ),
        (
            "eye_target",
            ("target = [0.0, 0.0, 0.0]", "target = [0.0, 6.0, 8.0]"),
            "camera.eye = [0.0, 6.0, 8.0] and camera.target = [0.0, 6.0, 8.0] coincide: the camera has no view direction",
        ),
        (
            "subpixel",
            ("fov_y_deg = 45.0", "fov_y_deg = 178.0"),
            "the meshes are in view but smaller than one pixel at 32x32 (camera.fov_y_deg = 178, camera.eye = [0.0, 6.0, 8.0]): narrow the field of view, move the camera closer or raise the resolution",
        ),
    ];
    for (case, (from, to), want) in cases {
        refused(
            case,
            &with(from, to),
            &render(&[]),
            &format!("scene.toml: {want}"),
        );
    }
}

#[test]
fn empty_scene_names_are_refused() {
    let builtins = penumbra::research::scene::builtin_names().join(", ");
    let want = format!(
        "--scene \"\": empty; give a built-in scene ({builtins}) or a path to a scene TOML file"
    );
    for command in ["render", "compare", "sequence"] {
        refused(
            &format!("empty_{command}"),
            SCENE,
            &[command, "--scene", "", "--out", "out"],
            &want,
        );
    }
    refused(
        "empty_name",
        &with("name = \"tiny\"", "name = \"\""),
        &render(&[]),
        "scene.toml: name = \"\": a scene's name must not be empty (leave `name` out to use the file's)",
    );
}

#[test]
fn sequence_paths_are_bounded_by_the_scene() {
    let seq = |extra: &[&'static str]| {
        [
            &[
                "sequence",
                "--scene",
                "scene.toml",
                "--methods",
                "hard",
                "--frames",
                "2",
                "--out",
                "out",
            ],
            extra,
        ]
        .concat()
    };
    // The tiny scene's diagonal: the plane spans 10 x 10, the box reaches y = 1.5.
    let diagonal = (200.0f32 + 1.5 * 1.5).sqrt();
    let limit = format!(
        "beyond 100 × the scene's diagonal of {diagonal:.1} (at most {:.1})",
        100.0 * diagonal
    );
    refused(
        "offset_1e30",
        SCENE,
        &seq(&["--offset", "1e30,0,0"]),
        &format!("--offset 1e30,0,0: reaches 1e30, {limit}"),
    );
    refused(
        "offset_2e3",
        SCENE,
        &seq(&["--offset", "0,-2000,0"]),
        &format!("--offset 0,-2000,0: reaches 2e3, {limit}"),
    );
    refused(
        "radius",
        SCENE,
        &seq(&[
            "--animate",
            "occluder",
            "--path",
            "circle",
            "--radius",
            "1e9",
        ]),
        &format!("--radius 1000000000: reaches 1e9, {limit}"),
    );
    // Within the scene's reach but past the coordinate bound of the scene file.
    // (The light faces the scene from the side: a light 1e6 to the side facing down is refused at
    // load, its maps not seeing the scene.)
    let far = SCENE.replace(
        "center = [0.0, 8.0, 0.0]\nedge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 2.0]",
        "center = [999990.0, 8.0, 0.0]\nedge_u = [0.0, 0.0, 2.0]\nedge_v = [0.0, 2.0, 0.0]",
    );
    assert_ne!(far, SCENE);
    refused(
        "offset_bound",
        &far,
        &seq(&["--offset", "100,0,0"]),
        "--offset 100,0,0: moves the light beyond ±1e6, the scene file's coordinate bound",
    );
}

#[test]
fn method_parameters_in_set_say_where_they_go() {
    let both = "p_m is a parameter of methods adaptive, env-adaptive, not a render setting";
    refused(
        "pm_render",
        SCENE,
        &render(&["--set", "p_m=10"]),
        &format!(
            "--set p_m=10: {both}; write it in the method spec (adaptive:p_m=10) or --param p_m=10"
        ),
    );
    refused(
        "kernel_render",
        SCENE,
        &["render", "--scene", "scene.toml", "--method", "pcf", "--set", "render.kernel=box", "--out", "out"],
        "--set render.kernel=box: kernel is a parameter of method pcf, not a render setting; write it in the method spec (pcf:kernel=box) or --param kernel=box",
    );
    refused(
        "pm_compare",
        SCENE,
        &[
            "compare",
            "--scene",
            "scene.toml",
            "--methods",
            "hard",
            "--set",
            "p_m=10",
            "--out",
            "out",
        ],
        &format!("--set p_m=10: {both}; write it in the method spec (adaptive:p_m=10)"),
    );
    refused(
        "twice",
        SCENE,
        &[
            "render",
            "--scene",
            "scene.toml",
            "--method",
            "adaptive:p_m=1",
            "--param",
            "p_m=10",
            "--out",
            "out",
        ],
        "method `adaptive:p_m=1`: `p_m` is given twice (1, and 10 with --param)",
    );
    let help =
        String::from_utf8_lossy(&common::penumbra(&["render", "--help"]).stdout).replace('\n', " ");
    assert!(
        help.contains("--set <KEY=VALUE>    Override a render setting"),
        "{help}"
    );
    assert!(
        help.contains("--param <KEY=VALUE>  A parameter of --method"),
        "{help}"
    );
}

fn run_json(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("out/run.json")).unwrap()).unwrap()
}

#[test]
fn set_cull_is_the_render_setting_in_render_and_apart_from_adaptives_cull() {
    let _ = common::gpu(); // fails here, with instructions, when no adapter exists
    for cull in ["none", "front", "back"] {
        let dir = folder(&format!("cull_render_{cull}"), SCENE);
        let set = format!("cull={cull}");
        let out = run_in(
            &dir,
            &[
                "render",
                "--scene",
                "scene.toml",
                "--method",
                "hard",
                "--set",
                &set,
                "--out",
                "out",
            ],
        );
        assert_eq!(
            out.status.code(),
            Some(0),
            "{cull}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(run_json(&dir)["render"]["cull"], cull);
    }
    // Adaptive's own cull in --param, the raster's in --set: both recorded, neither taken for the other.
    let dir = folder("cull_both", SCENE);
    let args = [
        "render",
        "--scene",
        "scene.toml",
        "--method",
        "adaptive:scope=local",
        "--param",
        "cull=on",
        "--set",
        "cull=none",
        "--out",
        "out",
    ];
    let out = run_in(&dir, &args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let run = run_json(&dir);
    assert_eq!(
        (&run["render"]["cull"], &run["params"]["cull"]),
        (&serde_json::json!("none"), &serde_json::json!(true))
    );
    assert_eq!(run["label"], "adaptive:p_m=0,scope=local,cull=on");
}

#[test]
fn a_light_shut_in_a_box_warns_after_the_frame() {
    let _ = common::gpu();
    // With back faces culled, the box's inside casts nothing and V is mostly lit; without, V = 0.
    let dir = folder("enclosed_back", ENCLOSED);
    let out = run_in(
        &dir,
        &[
            "render",
            "--scene",
            "scene.toml",
            "--method",
            "hard",
            "--out",
            "out",
        ],
    );
    assert_eq!(out.status.code(), Some(0));
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lit = run_json(&dir)["mean_visibility"].as_f64().unwrap();
    assert!(lit > 0.5, "mean V {lit}");
    let dir = folder("enclosed_none", ENCLOSED);
    let out = run_in(
        &dir,
        &[
            "render",
            "--scene",
            "scene.toml",
            "--method",
            "hard",
            "--set",
            "cull=none",
            "--out",
            "out",
        ],
    );
    assert_eq!(out.status.code(), Some(0));
    let run = run_json(&dir);
    assert_eq!(run["mean_visibility"], 0.0);
    let n = run["geometry_pixels"].as_u64().unwrap();
    assert!(n > 500, "{n} geometry pixels");
    let stderr = String::from_utf8_lossy(&out.stderr);
    let want = format!("warning: scene.toml: V = 0 at all {n} geometry pixels: no light reaches any visible surface (is the light enclosed by a mesh?)");
    assert_eq!(stderr.lines().collect::<Vec<_>>(), [want]);
    for f in ["visibility.png", "visibility.exr", "shaded.png", "run.json"] {
        assert!(dir.join("out").join(f).is_file(), "{f} missing");
    }
}

#[test]
fn set_cull_is_accepted_by_compare_and_sweep_and_recorded() {
    let _ = common::gpu();
    for (command, cull) in [
        ("compare", "none"),
        ("compare", "front"),
        ("sweep", "back"),
        ("sweep", "none"),
    ] {
        let dir = folder(&format!("cull_{command}_{cull}"), SCENE);
        std::fs::write(dir.join("spec.toml"), "methods = [\"hard\"]\n").unwrap();
        let set = format!("cull={cull}");
        let mut args = vec![
            command,
            "--scene",
            "scene.toml",
            "--set",
            &set,
            "--repeats",
            "1",
            "--samples",
            "4",
            "--no-cache",
            "--out",
            "out",
        ];
        args.extend(if command == "compare" {
            ["--methods", "hard"]
        } else {
            ["--spec", "spec.toml"]
        });
        let out = run_in(&dir, &args);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{command} {cull}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let rows = common::rows(&dir.join("out"));
        assert_eq!(rows.len(), 1, "{command}");
        assert_eq!(
            rows[0]["provenance"]["overrides"],
            serde_json::json!([set]),
            "{command}"
        );
        assert_eq!(rows[0]["method"], "hard");
    }
}
