//! Every bad input gives one clear line naming the file and the problem, a non-zero exit, no panic
//! and no output file.

#[macro_use]
mod common;
use common::{penumbra, temp_dir};
use std::path::Path;

const GOOD: &str = concat!(
    tiny_scene_head!(),
    r#"
[[mesh]]
builtin = "plane"
scale = 10.0

[[mesh]]
file = "tri.obj"
"#
);

const TRI: &str = "v 0 1 0\nv 1 1 0\nv 0 1 1\nf 1 2 3\n";

/// Writes the scene and mesh, runs `render`, and checks the common contract; returns stderr.
fn fails(case: &str, scene: &str, mesh: Option<&str>, extra: &[&str]) -> String {
    let dir = temp_dir(case);
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    if let Some(m) = mesh {
        std::fs::write(dir.join("tri.obj"), m).unwrap();
    }
    let out_dir = dir.join("out");
    let scene_path = dir.join("scene.toml");
    let mut args = vec![
        "render",
        "--scene",
        scene_path.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let out = penumbra(&args);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(
        !out.status.success(),
        "{case}: expected failure, got success"
    );
    assert_eq!(
        out.status.code(),
        Some(1),
        "{case}: exit code {:?}, stderr: {stderr}",
        out.status.code()
    );
    assert!(!stderr.contains("panicked"), "{case}: panicked: {stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(
        lines.len(),
        1,
        "{case}: expected one error line, got: {stderr}"
    );
    assert!(
        !Path::new(&out_dir).exists(),
        "{case}: output folder was created"
    );
    lines[0].to_string()
}

#[test]
fn good_scene_renders() {
    let dir = temp_dir("good");
    std::fs::write(dir.join("scene.toml"), GOOD).unwrap();
    std::fs::write(dir.join("tri.obj"), TRI).unwrap();
    let out = penumbra(&[
        "render",
        "--scene",
        dir.join("scene.toml").to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for f in ["visibility.png", "visibility.exr", "shaded.png", "run.json"] {
        assert!(dir.join("out").join(f).exists(), "{f} missing");
    }
}

#[test]
fn toml_syntax_error_names_line_and_column() {
    let e = fails(
        "syntax",
        &GOOD.replace("fov_y_deg = 45.0", "fov_y_deg = = 45.0"),
        Some(TRI),
        &[],
    );
    assert!(
        e.contains("scene.toml") && e.contains("line 5, column"),
        "{e}"
    );
}

#[test]
fn unknown_key() {
    let e = fails(
        "unknown",
        &GOOD.replace("fov_y_deg", "fov_y_deg = 45.0\nzoom"),
        Some(TRI),
        &[],
    );
    assert!(
        e.contains("scene.toml") && e.contains("unknown field `zoom`"),
        "{e}"
    );
}

#[test]
fn missing_mesh_file() {
    let e = fails("missing-mesh", GOOD, None, &[]);
    assert!(
        e.contains(
            "scene.toml: mesh 2: file = \"tri.obj\": cannot read: No such file or directory"
        ) && e.matches("tri.obj").count() == 1,
        "{e}"
    );
}

#[test]
fn unreadable_mesh_file() {
    let dir = temp_dir("unreadable-mesh");
    std::fs::create_dir_all(dir.join("tri.obj")).unwrap(); // a folder where a file should be
    std::fs::write(dir.join("scene.toml"), GOOD).unwrap();
    let out = penumbra(&[
        "render",
        "--scene",
        dir.join("scene.toml").to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
    ]);
    let e = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        e.contains("mesh 2: file = \"tri.obj\": ")
            && e.contains("tri.obj is a folder, not a regular file")
            && !e.contains("panicked"),
        "{e}"
    );
}

#[test]
fn malformed_mesh() {
    let e = fails(
        "malformed-mesh",
        GOOD,
        Some("v 0 1 0\nv 1 1 0\nf 1 2 7\n"),
        &[],
    );
    assert!(
        e.contains("mesh 2: file = \"tri.obj\": line 3") && e.contains("vertex 7"),
        "{e}"
    );
}

#[test]
fn nan_coordinate_in_mesh() {
    let e = fails(
        "nan-mesh",
        GOOD,
        Some("v 0 1 0\nv 1 NaN 0\nv 0 1 1\nf 1 2 3\n"),
        &[],
    );
    assert!(
        e.contains("mesh 2: file = \"tri.obj\": line 2") && e.contains("NaN"),
        "{e}"
    );
}

#[test]
fn nan_coordinate_in_scene() {
    let e = fails(
        "nan-scene",
        &GOOD.replace("center = [0.0, 8.0, 0.0]", "center = [0.0, nan, 0.0]"),
        Some(TRI),
        &[],
    );
    assert!(
        e.contains("scene.toml") && e.contains("light.center") && e.contains("NaN"),
        "{e}"
    );
}

#[test]
fn empty_mesh() {
    let e = fails("empty-mesh", GOOD, Some("# no faces\nv 0 0 0\n"), &[]);
    assert!(e.contains("tri.obj") && e.contains("empty"), "{e}");
}

#[test]
fn zero_area_light() {
    let e = fails(
        "zero-light",
        &GOOD.replace("edge_v = [0.0, 0.0, 2.0]", "edge_v = [4.0, 0.0, 0.0]"),
        Some(TRI),
        &[],
    );
    assert!(e.contains("scene.toml") && e.contains("zero area"), "{e}");
}

#[test]
fn zero_resolution() {
    let e = fails("zero-res", GOOD, Some(TRI), &["--set", "width=0"]);
    assert!(
        e.contains("scene.toml") && e.contains("render.width must be at least 1"),
        "{e}"
    );
}

#[test]
fn resolution_beyond_device_limit() {
    let e = fails("huge-res", GOOD, Some(TRI), &["--set", "resolution=100000"]);
    assert!(e.contains("resolution = 100000 (100000x100000): the G-buffer needs a side of 100000 texels, over this device's max_texture_dimension_2d"), "{e}");
}

#[test]
fn shadow_map_beyond_device_limit() {
    let e = fails(
        "huge-map",
        GOOD,
        Some(TRI),
        &["--set", "shadow_map_size=100000"],
    );
    assert!(e.contains("shadow_map_size = 100000: a shadow map needs a side of 100000 texels, over this device's max_texture_dimension_2d"), "{e}");
}

#[test]
fn unknown_method_and_parameter() {
    let e = fails("bad-method", GOOD, Some(TRI), &["--method", "pcss9"]);
    assert!(e.contains("unknown method `pcss9`"), "{e}");
    let e = fails("bad-param", GOOD, Some(TRI), &["--method", "regular:p_m=3"]);
    assert!(e.contains("method `regular` has no parameter `p_m`"), "{e}");
    let e = fails(
        "bad-items",
        GOOD,
        Some(TRI),
        &["--method", "adaptive:scope=local,items=0"],
    );
    assert!(e.contains("items = `0`") && e.contains("at least 1"), "{e}");
    let e = fails(
        "items-global",
        GOOD,
        Some(TRI),
        &["--method", "adaptive:items=100"],
    );
    assert!(e.contains("items needs scope = local"), "{e}");
}

#[test]
fn bad_environment_method_values() {
    let e = fails(
        "bad-env-at",
        GOOD,
        Some(TRI),
        &["--method", "env-pixels:at=face"],
    );
    assert!(
        e.contains("env-pixels: parameter at = `face`: use one of pixel, vertex"),
        "{e}"
    );
    let e = fails(
        "bad-env-filter",
        GOOD,
        Some(TRI),
        &["--method", "env-shadowmaps:filter=gauss"],
    );
    assert!(e.contains("env-shadowmaps: parameter filter = `gauss`: use one of box, bilinear, poisson, stratified, rotated"), "{e}");
    let e = fails(
        "bad-env-taps",
        GOOD,
        Some(TRI),
        &["--method", "env-shadowmaps:filter=rotated,taps=7"],
    );
    assert!(
        e.contains("env-shadowmaps: taps = 7 with filter = rotated: use 4, 16, 32 or 64"),
        "{e}"
    );
}

#[test]
fn missing_scene_file() {
    let out = penumbra(&[
        "render",
        "--scene",
        "/nonexistent/scene.toml",
        "--out",
        "/tmp/never",
    ]);
    let e = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        e.contains("/nonexistent/scene.toml") && e.contains("no such scene file"),
        "{e}"
    );
}

#[test]
fn no_vulkan_driver_stops_at_once_naming_it_and_the_setup_script() {
    // The loader pointed at no driver: lavapipe's GL adapter may remain, which cannot run the pipeline.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(["info"])
        .env("VK_ICD_FILENAMES", "/nonexistent")
        .env("VK_DRIVER_FILES", "/nonexistent")
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{e}");
    assert_eq!(e.lines().count(), 1, "one line: {e}");
    assert!(
        e.contains("no Vulkan driver")
            && e.contains("`bash scripts/setup.sh`")
            && e.contains("mesa-vulkan-drivers"),
        "{e}"
    );
}

#[test]
fn unmatched_adapter_name_lists_the_adapters_seen() {
    let out = penumbra(&["info", "--adapter", "no-such-adapter-anywhere"]);
    let e = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{e}");
    assert!(e.starts_with("error: adapter name \"no-such-adapter-anywhere\": no adapter's name contains it (adapters seen: "), "{e}");
}

#[test]
fn info_says_which_backend_was_chosen_and_why() {
    let out = penumbra(&["info"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("backend:      Vulkan"), "{text}");
    assert!(
        text.contains("chosen:       auto: Vulkan preferred"),
        "{text}"
    );
    let out = penumbra(&["info", "--backend", "vulkan"]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("chosen:       --backend vulkan"));
}

#[test]
fn hybrid_map_settings_are_checked() {
    let e = fails(
        "hybrid-levels",
        GOOD,
        Some(TRI),
        &["--set", "maps=hybrid", "--set", "levels=3"],
    );
    assert!(
        e.contains("scene.toml") && e.contains("render.hybrid.levels = 3: use 1 or 2"),
        "{e}"
    );
    let e = fails(
        "hybrid-base",
        GOOD,
        Some(TRI),
        &["--set", "maps=hybrid", "--set", "base=250"],
    );
    assert!(
        e.contains("render.hybrid.base = 250") && e.contains("multiple of 2^levels = 4"),
        "{e}"
    );
    let e = fails(
        "hybrid-eps",
        GOOD,
        Some(TRI),
        &["--set", "maps=hybrid", "--set", "eps=-1"],
    );
    assert!(e.contains("render.hybrid.eps = -1"), "{e}");
    let e = fails("maps-kind", GOOD, Some(TRI), &["--set", "maps=sparse"]);
    assert!(
        e.contains("maps=sparse") && e.contains("`plain` or `hybrid`"),
        "{e}"
    );
    let e = fails(
        "hybrid-esm",
        GOOD,
        Some(TRI),
        &[
            "--method",
            "esm",
            "--set",
            "maps=hybrid",
            "--set",
            "base=64",
        ],
    );
    assert!(e.contains("esm: maps = hybrid is not supported"), "{e}");
    let e = fails(
        "hybrid-local",
        GOOD,
        Some(TRI),
        &[
            "--method",
            "adaptive:scope=local",
            "--set",
            "maps=hybrid",
            "--set",
            "base=64",
        ],
    );
    assert!(
        e.contains("adaptive: maps = hybrid needs scope = global"),
        "{e}"
    );
}

#[test]
fn reference_point_is_checked() {
    let dir = temp_dir("reference-point");
    let out_dir = dir.join("out");
    for (args, want) in [
        (
            vec!["--mode", "point", "--point", "2,0"],
            "reference point `2,0`: give S,T, two numbers in [0, 1]",
        ),
        (
            vec!["--mode", "lattice", "--point", "0.5,0.5"],
            "--point is for --mode point, not --mode lattice",
        ),
        (
            vec!["--mode", "pointy"],
            "reference mode `pointy`: use `lattice`, `continuous`, `point` or `point:S,T`",
        ),
    ] {
        let mut all = vec!["reference", "--out", out_dir.to_str().unwrap()];
        all.extend(args);
        let out = penumbra(&all);
        let stderr = String::from_utf8_lossy(&out.stderr).to_string();
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(
            stderr
                .lines()
                .any(|l| l.starts_with("error:") && l.contains(want)),
            "{stderr}"
        );
        assert!(!out_dir.exists(), "no output on bad input");
    }
}

#[test]
fn every_gpu_command_honours_the_adapter_request() {
    // sequence and failures used to open the default adapter whatever --adapter said.
    let dir = temp_dir("adapter-request");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    for args in [
        vec![
            "--adapter",
            "no-such-adapter-anywhere",
            "sequence",
            "--scene",
            "default",
            "--methods",
            "hard",
            "--frames",
            "2",
            "--out",
            o,
        ],
        vec![
            "--adapter",
            "no-such-adapter-anywhere",
            "failures",
            "--out",
            o,
        ],
    ] {
        let r = penumbra(&args);
        let e = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{args:?}: {e}");
        assert!(
            e.contains("adapter name \"no-such-adapter-anywhere\""),
            "{args:?}: {e}"
        );
        assert!(!out.exists(), "{args:?}: wrote output");
    }
}

#[test]
fn hybrid_study_flags_are_checked() {
    let dir = temp_dir("hybrid-study-flags");
    let out_dir = dir.join("out");
    for (flag, value, want) in [
        ("--hybrid", "2048/3", "--hybrid: map configuration `2048/3`: levels must be 1 or 2"),
        ("--hybrid", "1002/2", "--hybrid: map configuration `1002/2`: base must be in 8..=16384 and a multiple of 2^levels"),
        ("--plain", "abc", "--plain: map configuration `abc`: not a whole number"),
        ("--eps", "-1", "--eps: -1 must be a finite number >= 0"),
    ] {
        let arg = format!("{flag}={value}");
        let out = penumbra(&["hybrid", &arg, "--out", out_dir.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&out.stderr).to_string();
        assert_eq!(out.status.code(), Some(1), "{flag} {value}: {stderr}");
        assert!(stderr.lines().any(|l| l == format!("error: {want}")), "{flag} {value}: {stderr}");
        assert!(!out_dir.exists(), "no output on bad input");
    }
}

#[test]
fn warm_up_out_of_range_is_refused_naming_the_flag() {
    let dir = temp_dir("warm-up");
    let out_dir = dir.join("out");
    let out = penumbra(&[
        "render",
        "--warm-up",
        "1000",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr, "error: --warm-up: 1000 is not in 0..=100\n");
    assert!(!out_dir.exists(), "no output on bad input");
}
