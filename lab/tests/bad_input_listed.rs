//! The bad inputs listed for "a tool that never misleads": each is rejected with one line naming
//! the file or flag, the key and the value. Library checks need no GPU; the CLI cases check the
//! exit code, the single error line and that no output folder appears.

#[macro_use]
mod common;
use common::temp_dir;
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;

const BASE: &str = concat!(
    tiny_scene_head!(),
    r#"
[[mesh]]
builtin = "plane"
scale = 10.0

[[mesh]]
builtin = "sphere"
translate = [0.0, 1.0, 0.0]
"#
);

fn scene_error(from: &str, to: &str) -> String {
    let text = BASE.replacen(from, to, 1);
    assert_ne!(text, BASE, "`{from}` is not in the base scene");
    Scene::parse(&text, "bad.toml", None, &[])
        .expect_err(&format!("`{to}` should be rejected"))
        .to_string()
}

fn assert_one_line(e: &str) {
    assert!(!e.contains('\n') && !e.is_empty(), "not one line: {e}");
}

#[test]
fn base_scene_is_accepted() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let s = Scene::parse(BASE, "bad.toml", None, &[]).unwrap();
    assert!(s.triangle_count() > 100);
}

#[test]
fn light_with_negative_size_is_rejected() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let e = scene_error(
        "edge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 2.0]",
        "size = [-1.0, 2.0]\nnormal = [0.0, -1.0, 0.0]",
    );
    assert_eq!(
        e,
        "bad.toml: light.size = [-1.0, 2.0]: both sides must be positive"
    );
}

#[test]
fn light_facing_away_from_every_mesh_is_rejected() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let e = scene_error(
        "edge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 2.0]",
        "size = [2.0, 2.0]\nnormal = [0.0, 1.0, 0.0]",
    );
    assert!(
        e.starts_with("bad.toml: light: emits along [") && e.contains("away from every mesh"),
        "{e}"
    );
    // The same light given by edges in the other order.
    let e = scene_error("edge_v = [0.0, 0.0, 2.0]", "edge_v = [0.0, 0.0, -2.0]");
    assert!(
        e.contains("away from every mesh") && e.contains("swap edge_u and edge_v"),
        "{e}"
    );
    assert_one_line(&e);
}

#[test]
fn camera_or_light_far_beyond_f32_precision_is_rejected() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    for (from, to, key) in [
        (
            "eye = [0.0, 6.0, 8.0]",
            "eye = [0.0, 6.0, 1e30]",
            "camera.eye = [0.0, 6.0, 1e30]",
        ),
        (
            "center = [0.0, 8.0, 0.0]",
            "center = [0.0, 3e38, 0.0]",
            "light.center = [0.0, 3e38, 0.0]",
        ),
        (
            "edge_u = [2.0, 0.0, 0.0]",
            "edge_u = [1e20, 0.0, 0.0]",
            "light.edge_u = [1e20, 0.0, 0.0]",
        ),
    ] {
        let e = scene_error(from, to);
        assert_eq!(e, format!("bad.toml: {key}: coordinates must be within ±1e6 (f32 has no precision left beyond)"));
    }
}

#[test]
fn sphere_segments_below_three_are_rejected_not_clamped() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    for n in [0, 1, 2] {
        let e = scene_error("translate = [0.0, 1.0, 0.0]", &format!("segments = {n}"));
        assert_eq!(
            e,
            format!("bad.toml: mesh 2: segments = {n} for a sphere: must be in 3..=512")
        );
    }
}

#[test]
fn type_errors_name_the_line_the_table_the_key_and_the_value() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let e = scene_error("scale = 10.0", "scale = \"big\"");
    assert_eq!(e, "bad.toml: at line 19, column 9: [[mesh]] #1 scale = \"big\": expected a number or an array [x, y, z]");
    let e = scene_error("fov_y_deg = 45.0", "fov_y_deg = \"wide\"");
    assert_eq!(e, "bad.toml: at line 5, column 13: [camera] fov_y_deg = \"wide\": invalid type: string \"wide\", expected f32");
}

#[test]
fn non_finite_bias_or_ambient_names_the_key() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let e = scene_error(
        "shadow_map_size = 64",
        "shadow_map_size = 64\nambient = nan",
    );
    assert_eq!(e, "bad.toml: render.ambient = NaN: must be a finite number");
    let e = scene_error(
        "shadow_map_size = 64",
        "shadow_map_size = 64\nbias = { slope = inf }",
    );
    assert_eq!(
        e,
        "bad.toml: render.bias.slope = inf: must be a finite number"
    );
}

#[test]
fn set_type_errors_name_set_and_the_key_not_the_scene_file() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
                             // The engine's error is typed and names no flag; the command line words it as `--set`.
    let e = Scene::parse(
        BASE,
        "bad.toml",
        None,
        &[("resolution".into(), "abc".into())],
    )
    .unwrap_err();
    assert!(
        matches!(&e, penumbra::Error::Setting { key, value: Some(v), .. } if key == "resolution" && v == "abc"),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "resolution=abc: invalid type: string \"abc\", expected u32"
    );
    assert_eq!(
        penumbra_lab::cli_words(&e),
        "--set resolution=abc: invalid type: string \"abc\", expected u32"
    );
    let e = Scene::parse(
        BASE,
        "bad.toml",
        None,
        &[
            ("width".into(), "64".into()),
            ("cull".into(), "sideways".into()),
        ],
    )
    .unwrap_err();
    assert_eq!(
        penumbra_lab::cli_words(&e),
        "--set cull=sideways: unknown variant `sideways`, expected one of `back`, `front`, `none`"
    );
    let e = Scene::parse(BASE, "bad.toml", None, &[("widht".into(), "64".into())]).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("bad.toml: widht: unknown render setting (known: width, "),
        "{e}"
    );
    assert!(
        penumbra_lab::cli_words(&e)
            .starts_with("bad.toml: --set widht: unknown render setting (known: width, "),
        "{e}"
    );
}

#[test]
fn duplicate_method_parameters_are_rejected() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let e = Method::parse("adaptive:p_m=1,p_m=2", &[])
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "method `adaptive:p_m=1,p_m=2`: `p_m` is given twice (1 and 2)"
    );
    // The engine says "apart from the spec"; the command line names its flag.
    let e = Method::parse("adaptive:p_m=1", &[("p_m".into(), "2".into())]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "method `adaptive:p_m=1`: `p_m` is given twice (1 in the spec, and 2 apart from it)"
    );
    assert_eq!(
        penumbra_lab::cli_words(&e),
        "method `adaptive:p_m=1`: `p_m` is given twice (1, and 2 with --param)"
    );
}

#[test]
fn p_m_inf_is_recorded_as_the_string_inf() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let m = Method::parse("adaptive:p_m=inf", &[]).unwrap();
    assert_eq!(m.params_json()["p_m"], "inf");
    assert_eq!(
        Method::parse("adaptive:p_m=16", &[]).unwrap().params_json()["p_m"],
        16.0
    );
}

#[test]
fn a_camera_that_sees_no_mesh_is_named_once() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let e = scene_error("target = [0.0, 0.0, 0.0]", "target = [0.0, 20.0, 30.0]");
    assert!(e.starts_with("bad.toml: no mesh is visible from the camera (camera.eye = [0.0, 6.0, 8.0], camera.target = [0.0, 20.0, 30.0]"), "{e}");
    assert_eq!(e.matches("no mesh is visible").count(), 1);
}

/// Runs the CLI in a fresh folder; checks exit 1, one `error:` line and no output folder.
fn cli_fails(case: &str, files: &[(&str, &str)], args: &[&str]) -> String {
    let dir = temp_dir(&format!("listed_{case}"));
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .current_dir(&dir)
        .args(args)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(1), "{case}: {e}");
    assert_eq!(e.lines().count(), 1, "{case}: {e}");
    assert!(!e.contains("panicked"), "{case}: {e}");
    assert!(!dir.join("out").exists(), "{case}: output written");
    e.trim().strip_prefix("error: ").unwrap_or(&e).to_string()
}

#[test]
fn a_camera_inside_the_bounds_that_sees_nothing_fails_after_the_g_buffer() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
                             // The bounding box is in view (so the scene loads); every pixel is sky.
    let scene = BASE
        .replace("eye = [0.0, 6.0, 8.0]", "eye = [4.0, 1.5, 4.0]")
        .replace("target = [0.0, 0.0, 0.0]", "target = [4.0, 10.0, 4.1]");
    let e = cli_fails(
        "sky",
        &[("s.toml", &scene)],
        &["render", "--scene", "s.toml", "--out", "out"],
    );
    assert!(
        e.starts_with("s.toml: no mesh is visible from the camera (camera.eye = [4.0, 1.5, 4.0]"),
        "{e}"
    );
}

#[test]
fn off_header_claiming_more_vertices_says_so() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let scene = BASE.replace("builtin = \"sphere\"", "file = \"m.off\"");
    let e = cli_fails(
        "off",
        &[
            ("s.toml", &scene),
            ("m.off", "OFF\n10 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
        ],
        &["render", "--scene", "s.toml", "--out", "out"],
    );
    assert_eq!(e, "s.toml: mesh 2: file = \"m.off\": line 2: file ends early: the counts say 10 vertices and 1 faces, but only 4 lines follow");
}

/// A mesh that cannot be read or parsed: one line naming the scene file, the mesh (its `[[mesh]]`
/// table, counted from 1) and the mesh file once.
#[test]
fn mesh_read_errors_name_the_scene_the_mesh_and_the_file_once() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    for (case, file, text, want) in [
        ("missing_obj", "gone.obj", None, "s.toml: mesh 2: file = \"gone.obj\": cannot read: No such file or directory (os error 2)"),
        ("missing_off", "gone.off", None, "s.toml: mesh 2: file = \"gone.off\": cannot read: No such file or directory (os error 2)"),
        ("bad_obj", "bad.obj", Some("v 1 2\nf 1 2 3\n"), "s.toml: mesh 2: file = \"bad.obj\": line 1: vertex needs 3 coordinates, found 2"),
    ] {
        let scene = BASE.replace("builtin = \"sphere\"", &format!("file = \"{file}\""));
        let mut files = vec![("s.toml", scene.as_str())];
        files.extend(text.map(|t| (file, t)));
        let e = cli_fails(case, &files, &["render", "--scene", "s.toml", "--out", "out"]);
        assert_eq!(e, want, "{case}");
        assert_eq!(e.matches(file).count(), 1, "{case}: the path once: {e}");
    }
}

#[test]
fn truncated_ply_header_is_one_plain_line() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let scene = BASE.replace("builtin = \"sphere\"", "file = \"m.ply\"");
    let e = cli_fails(
        "ply",
        &[
            ("s.toml", &scene),
            ("m.ply", "ply\nformat ascii 1.0\nelement vertex 3\nprop"),
        ],
        &["render", "--scene", "s.toml", "--out", "out"],
    );
    assert!(
        e.starts_with(
            "s.toml: mesh 2: file = \"m.ply\": line 4: header line `prop` is not a PLY header line"
        ),
        "{e}"
    );
    assert!(
        !e.contains("ParseError") && !e.contains("ExpectedSet"),
        "{e}"
    );
}

#[test]
fn sweep_spec_errors_give_the_position_or_the_grid() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let e = cli_fails(
        "sweep_syntax",
        &[("s.toml", "methods = [\"hard\"\n[[grid]]\n")],
        &["sweep", "--spec", "s.toml", "--out", "out"],
    );
    assert_eq!(
        e,
        "s.toml: line 2, column 1: missing comma between array elements, expected `,`"
    );
    let spec =
        "[[grid]]\nmethod = \"regular\"\nn = [3]\n[[grid]]\nmethod = \"adaptive\"\nfoo = [1, 2]\n";
    let e = cli_fails(
        "sweep_grid",
        &[("s.toml", spec)],
        &["sweep", "--spec", "s.toml", "--out", "out"],
    );
    assert!(e.starts_with("s.toml: grid 2 (adaptive:foo=1): method `adaptive` has no parameter `foo` (its parameters: "), "{e}");
}

#[test]
fn report_rejects_a_file_given_twice_and_says_each_error_once() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let e = cli_fails(
        "report_twice",
        &[("a.jsonl", "")],
        &["report", "a.jsonl", "./a.jsonl", "--out", "out"],
    );
    assert_eq!(e, "report: ./a.jsonl is given twice");
    let e = cli_fails(
        "report_missing",
        &[],
        &["report", "none.jsonl", "--out", "out"],
    );
    assert_eq!(e.matches("none.jsonl").count(), 1, "{e}");
    assert!(e.contains("cannot read results file"), "{e}");
}

#[test]
fn set_errors_through_the_cli_name_set() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let e = cli_fails(
        "set_abc",
        &[("s.toml", BASE)],
        &[
            "render",
            "--scene",
            "s.toml",
            "--set",
            "resolution=abc",
            "--out",
            "out",
        ],
    );
    assert_eq!(
        e,
        "--set resolution=abc: invalid type: string \"abc\", expected u32"
    );
}

/// Mesh files must be regular files under the cap (`--max-mesh-mib`): a FIFO would block the
/// open forever, a link to /dev/zero would be read until memory runs out.
#[cfg(target_os = "linux")]
mod mesh_files {
    use super::*;
    use std::time::{Duration, Instant};

    fn scene_with(file: &str) -> String {
        BASE.replace("builtin = \"sphere\"", &format!("file = \"{file}\""))
    }

    /// As `cli_fails`, for a case whose files the caller made, and within a time limit: a
    /// blocked open must fail the test, not hang it.
    fn cli_fails_promptly(dir: &std::path::Path, args: &[&str]) -> String {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
            .current_dir(dir)
            .args(args)
            .env("PENUMBRA_NO_PROGRESS", "1")
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let start = Instant::now();
        while child.try_wait().unwrap().is_none() {
            if start.elapsed() > Duration::from_secs(60) {
                child.kill().unwrap();
                panic!("penumbra {args:?} still runs after 60 s");
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let out = child.wait_with_output().unwrap();
        let e = String::from_utf8_lossy(&out.stderr).to_string();
        assert_eq!(out.status.code(), Some(1), "{e}");
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(!dir.join("out").exists(), "output written");
        e.trim().strip_prefix("error: ").unwrap_or(&e).to_string()
    }

    /// One triangle padded with comment lines to `bytes`.
    fn padded_obj(bytes: usize) -> String {
        let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n");
        while text.len() < bytes {
            text.push_str("# padding to make the file large enough to cross a small cap\n");
        }
        text
    }

    #[test]
    fn a_fifo_is_refused_without_opening_it() {
        let dir = temp_dir("listed_fifo");
        std::fs::write(dir.join("s.toml"), scene_with("x.obj")).unwrap();
        let fifo = std::ffi::CString::new(dir.join("x.obj").to_str().unwrap()).unwrap();
        assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o644) }, 0);
        let e = cli_fails_promptly(&dir, &["render", "--scene", "s.toml", "--out", "out"]);
        assert_eq!(
            e,
            "s.toml: mesh 2: file = \"x.obj\": x.obj is a FIFO, not a regular file"
        );
    }

    #[test]
    fn a_link_to_dev_zero_is_refused() {
        let dir = temp_dir("listed_dev_zero");
        std::fs::write(dir.join("s.toml"), scene_with("z.obj")).unwrap();
        std::os::unix::fs::symlink("/dev/zero", dir.join("z.obj")).unwrap();
        let e = cli_fails_promptly(&dir, &["render", "--scene", "s.toml", "--out", "out"]);
        assert_eq!(e, "s.toml: mesh 2: file = \"z.obj\": z.obj (a link to /dev/zero) is a character device, not a regular file");
    }

    #[test]
    fn a_folder_is_refused() {
        let dir = temp_dir("listed_mesh_folder");
        std::fs::write(dir.join("s.toml"), scene_with("d.obj")).unwrap();
        std::fs::create_dir(dir.join("d.obj")).unwrap();
        let e = cli_fails_promptly(&dir, &["render", "--scene", "s.toml", "--out", "out"]);
        assert_eq!(
            e,
            "s.toml: mesh 2: file = \"d.obj\": d.obj is a folder, not a regular file"
        );
    }

    #[test]
    fn a_file_over_the_cap_is_refused_and_loads_under_the_default() {
        let dir = temp_dir("listed_mesh_cap");
        let text = padded_obj(3 << 19);
        std::fs::write(dir.join("s.toml"), scene_with("big.obj")).unwrap();
        std::fs::write(dir.join("big.obj"), &text).unwrap();
        let len = text.len();
        let e = cli_fails_promptly(
            &dir,
            &[
                "--max-mesh-mib",
                "1",
                "render",
                "--scene",
                "s.toml",
                "--out",
                "out",
            ],
        );
        assert_eq!(
            e,
            format!("s.toml: mesh 2: file = \"big.obj\": big.obj is 1.5 MiB ({len} bytes), over the 1 MiB cap on mesh files (raise it with --max-mesh-mib N)")
        );
        // The flag is global: after the command too.
        let e = cli_fails_promptly(
            &dir,
            &[
                "render",
                "--scene",
                "s.toml",
                "--out",
                "out",
                "--max-mesh-mib",
                "1",
            ],
        );
        assert!(
            e.ends_with("over the 1 MiB cap on mesh files (raise it with --max-mesh-mib N)"),
            "{e}"
        );
        let scene = Scene::load(dir.join("s.toml").to_str().unwrap(), &[]).unwrap();
        assert!(scene.triangle_count() > 2);
    }

    #[test]
    fn a_gzip_bomb_stops_at_the_cap() {
        use penumbra::research::scene::MeshDirs;
        use std::io::Write;
        let dir = temp_dir("listed_gzip_bomb");
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
        gz.write_all(b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\ncomment ").unwrap();
        gz.write_all(&vec![b'a'; 3 << 20]).unwrap();
        std::fs::write(dir.join("m.ply.gz"), gz.finish().unwrap()).unwrap();
        let dirs = MeshDirs {
            scene_dir: Some(&dir),
            cache: None,
            max_mesh_bytes: Some(1 << 20),
        };
        let e = Scene::parse_in(&scene_with("m.ply.gz"), "s.toml", dirs, &[])
            .unwrap_err()
            .to_string();
        assert_one_line(&e);
        assert!(
            e.starts_with("s.toml: mesh 2: file = \"m.ply.gz\": decompresses to more"),
            "{e}"
        );
        assert!(e.contains("decompresses to more than the 1 MiB cap on mesh files (raise it with --max-mesh-mib N)"), "{e}");
    }
}
