//! The scene-format additions, on tiny files written here: registry mesh formats in scenes, the
//! `cache:` prefix (resolved in a temporary cache), the missing-cache message, subdivision and
//! instancing. No GPU.

#[macro_use]
mod common;
use common::{penumbra, temp_dir};
use glam::Vec3;
use penumbra::research::scene::{MeshDirs, Scene};
use std::path::Path;

const HEAD: &str = tiny_scene_head!();

/// One triangle with a vertex at the origin, in OFF.
const TRI_OFF: &str = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 0 1\n3 0 2 1\n";

fn parse(dir: &Path, cache: Option<&Path>, meshes: &str) -> penumbra::Result<Scene> {
    let text = format!("{HEAD}\n{meshes}");
    Scene::parse_in(
        &text,
        "test.toml",
        MeshDirs {
            scene_dir: Some(dir),
            cache,
            max_mesh_bytes: None,
        },
        &[],
    )
}

fn centroid(scene: &Scene) -> Vec3 {
    scene
        .vertices
        .iter()
        .map(|v| Vec3::from(v.position))
        .sum::<Vec3>()
        / scene.vertices.len() as f32
}

#[test]
fn every_registry_format_loads_from_the_scene_folder() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = temp_dir("scene_formats");
    std::fs::write(dir.join("tri.off"), TRI_OFF).unwrap();
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
               element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 0 1\n3 0 2 1\n";
    std::fs::write(dir.join("tri.ply"), ply).unwrap();
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut gz, ply.as_bytes()).unwrap();
    std::fs::write(dir.join("tri.ply.gz"), gz.finish().unwrap()).unwrap();
    std::fs::write(
        dir.join("tri.js"),
        "exports.positions=[[0,0,0],[1,0,0],[0,0,1]]\nexports.cells=[[0,2,1]]\n",
    )
    .unwrap();
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 3 2\n").unwrap();
    for file in ["tri.off", "tri.ply", "tri.ply.gz", "tri.js", "tri.obj"] {
        let text = format!("triangles = 1\n{HEAD}\n[[mesh]]\nfile = \"{file}\"\n");
        let scene = Scene::parse_in(
            &text,
            "test.toml",
            MeshDirs {
                scene_dir: Some(&dir),
                cache: None,
                max_mesh_bytes: None,
            },
            &[],
        );
        let scene = scene.unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(scene.triangle_count(), 1, "{file}");
        assert_eq!(scene.vertices[0].position, [0.0, 0.0, 0.0], "{file}");
        // Wound towards +y: the area-weighted normal points up.
        assert!(
            scene.vertices[0].normal[1] > 0.99,
            "{file}: {:?}",
            scene.vertices[0].normal
        );
    }
}

#[test]
fn unknown_mesh_extension_is_named() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = temp_dir("scene_unknown_ext");
    std::fs::write(dir.join("tri.stl"), "solid").unwrap();
    let e = parse(&dir, None, "[[mesh]]\nfile = \"tri.stl\"\n")
        .unwrap_err()
        .to_string();
    assert_eq!(e, "test.toml: mesh 1: file = \"tri.stl\": unknown mesh format (expected .obj, .off, .ply, .ply.gz or .js)");
}

#[test]
fn mesh_errors_name_the_mesh_file_and_line() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = temp_dir("scene_bad_mesh");
    std::fs::write(
        dir.join("bad.off"),
        "OFF\n3 1 0\n0 0 0\n1 0 0\n0 0 1\n3 0 2 7\n",
    )
    .unwrap();
    let e = parse(&dir, None, "[[mesh]]\nfile = \"bad.off\"\n")
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "test.toml: mesh 1: file = \"bad.off\": line 6, face 0: references vertex 7 of 3"
    );
}

#[test]
fn cache_prefix_resolves_in_the_given_cache() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = temp_dir("scene_cache_scene");
    let cache = temp_dir("scene_cache_root");
    std::fs::create_dir_all(cache.join("meshes")).unwrap();
    std::fs::write(cache.join("meshes/tri.off"), TRI_OFF).unwrap();
    let scene = parse(
        &dir,
        Some(&cache),
        "[[mesh]]\nfile = \"cache:meshes/tri.off\"\ntranslate = [2.0, 0.0, 0.0]\n",
    )
    .unwrap();
    assert_eq!(scene.triangle_count(), 1);
    assert_eq!(scene.vertices[0].position, [2.0, 0.0, 0.0]);
}

#[test]
fn missing_cache_file_says_how_to_fetch_it() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = temp_dir("scene_cache_missing");
    let cache = temp_dir("scene_cache_empty");
    let e = parse(
        &dir,
        Some(&cache),
        "[[mesh]]\nfile = \"cache:meshes/cow.off\"\n",
    )
    .unwrap_err();
    // The engine names the group; the command line says how to fetch it.
    assert!(matches!(e, penumbra::Error::MissingAsset { ref group, .. } if group == "meshes"));
    assert_eq!(
        penumbra_lab::cli_words(&e),
        format!(
            "test.toml: mesh 1: file = \"cache:meshes/cow.off\": not in the asset cache ({} is missing): run `penumbra assets fetch --group meshes` (cache folder: --cache or $PENUMBRA_CACHE)",
            cache.join("meshes/cow.off").display()
        )
    );
    let e = parse(
        &dir,
        Some(&cache),
        "[[mesh]]\nfile = \"cache:trees/oak_large.obj\"\n",
    )
    .unwrap_err();
    let e = penumbra_lab::cli_words(&e);
    assert!(e.contains("penumbra assets fetch --group trees"), "{e}");
    let e = parse(
        &dir,
        Some(&cache),
        "[[mesh]]\nfile = \"cache:../escape.off\"\n",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("must be relative and stay inside the cache"),
        "{e}"
    );
}

#[test]
fn missing_cache_file_through_the_cli_is_one_line_and_no_output() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = temp_dir("scene_cache_cli");
    let cache = temp_dir("scene_cache_cli_root");
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        format!("{HEAD}\n[[mesh]]\nfile = \"cache:meshes/bunny00.off\"\n"),
    )
    .unwrap();
    let out_dir = dir.join("out");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args([
            "render",
            "--scene",
            scene.to_str().unwrap(),
            "--out",
            out_dir.to_str().unwrap(),
        ])
        .env("PENUMBRA_CACHE", &cache)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with(&format!(
            "error: {}: mesh 1: file = \"cache:meshes/bunny00.off\": not in the asset cache",
            scene.display()
        )),
        "{stderr}"
    );
    assert!(
        stderr.contains("penumbra assets fetch --group meshes"),
        "{stderr}"
    );
    assert!(!out_dir.exists());
}

#[test]
fn instances_place_copies_after_the_mesh_transform() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = temp_dir("scene_instances");
    let scene = parse(
        &dir,
        None,
        "[[mesh]]\nbuiltin = \"box\"\ntranslate = [0.0, 0.5, 0.0]\ninstances = [[10.0, 0.0, 0.0, 90.0, 2.0], [-10.0, 0.0, 0.0, 0.0, 1.0]]\n",
    )
    .unwrap();
    assert_eq!(scene.triangle_count(), 24);
    let (first, second) = scene.vertices.split_at(24);
    let c = |vs: &[penumbra::research::scene::Vertex]| {
        vs.iter().map(|v| Vec3::from(v.position)).sum::<Vec3>() / vs.len() as f32
    };
    // Scale 2 applies after the translate: the box's centre goes from y = 0.5 to y = 1.
    assert!(
        (c(first) - Vec3::new(10.0, 1.0, 0.0)).length() < 1e-5,
        "{}",
        c(first)
    );
    assert!(
        (c(second) - Vec3::new(-10.0, 0.5, 0.0)).length() < 1e-5,
        "{}",
        c(second)
    );
    // A 90° turn about y takes the +x face (the built-in box's first four vertices) to z = -1,
    // its normal to -z.
    for v in &first[..4] {
        assert!((v.position[2] + 1.0).abs() < 1e-5, "{:?}", v.position);
        assert!(
            (Vec3::from(v.normal) - Vec3::NEG_Z).length() < 1e-5,
            "{:?}",
            v.normal
        );
    }
}

#[test]
fn grid_is_centred_and_counts_match_the_stated_triangles() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = temp_dir("scene_grid");
    let text = format!("triangles = 72\n{HEAD}\n[[mesh]]\nbuiltin = \"box\"\ngrid = {{ count = [3, 2], spacing = [4.0, 6.0], rotate_step_deg = 30.0 }}\n");
    let scene = Scene::parse_in(
        &text,
        "grid.toml",
        MeshDirs {
            scene_dir: Some(&dir),
            cache: None,
            max_mesh_bytes: None,
        },
        &[],
    )
    .unwrap();
    assert_eq!(scene.triangle_count(), 6 * 12);
    assert!(centroid(&scene).length() < 1e-5);
    assert!(
        (scene.bounds.max.x - 4.0 - 0.5 * 2f32.sqrt()).abs() < 0.2,
        "{:?}",
        scene.bounds
    );
    let wrong = text.replace("triangles = 72", "triangles = 70");
    let e = Scene::parse_in(
        &wrong,
        "grid.toml",
        MeshDirs {
            scene_dir: Some(&dir),
            cache: None,
            max_mesh_bytes: None,
        },
        &[],
    )
    .unwrap_err()
    .to_string();
    assert_eq!(e, "grid.toml: states triangles = 70 but its meshes have 72");
}

#[test]
fn bad_instancing_is_reported_with_the_mesh_number() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = temp_dir("scene_bad_instances");
    let cases = [
        ("instances = []", "mesh 1: `instances` is empty"),
        ("instances = [[0.0, 0.0, 0.0, 0.0, -1.0]]", "mesh 1: instance 1: scale must be positive, got -1"),
        ("grid = { count = [0, 3], spacing = [1.0, 1.0] }", "mesh 1: grid.count must be at least [1, 1], got [0, 3]"),
        ("grid = { count = [1000, 1000], spacing = [1.0, 1.0] }", "mesh 1: grid of 1000000 instances (at most 100000)"),
        (
            "instances = [[0.0, 0.0, 0.0, 0.0, 1.0]]\ngrid = { count = [1, 1], spacing = [1.0, 1.0] }",
            "mesh 1: give either `instances` or `grid`, not both",
        ),
        ("subdivide = 14", "mesh 1: subdivide = 14 would turn 12 triangles into more than 33554432 (each level multiplies by 4)"),
    ];
    for (keys, expected) in cases {
        let e = parse(
            &dir,
            None,
            &format!("[[mesh]]\nbuiltin = \"box\"\n{keys}\n"),
        )
        .unwrap_err()
        .to_string();
        assert_eq!(e, format!("test.toml: {expected}"), "{keys}");
    }
    let e = parse(
        &dir,
        None,
        "[[mesh]]\nbuiltin = \"box\"\nsubdivision = \"catmull\"\n",
    )
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("test.toml: at line 19, column 15: [[mesh]] #1 subdivision = \"catmull\": unknown variant `catmull`"), "{e}");
}

#[test]
fn subdivision_multiplies_by_four_per_level() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = temp_dir("scene_subdivide");
    for scheme in ["midpoint", "loop"] {
        let s = parse(
            &dir,
            None,
            &format!("[[mesh]]\nbuiltin = \"box\"\nsubdivide = 2\nsubdivision = \"{scheme}\"\n"),
        )
        .unwrap();
        assert_eq!(s.triangle_count(), 12 * 16, "{scheme}");
        let radius = s
            .vertices
            .iter()
            .map(|v| Vec3::from(v.position).length())
            .fold(0.0f32, f32::max);
        match scheme {
            // The cube's corners stay where they are.
            "midpoint" => assert!((radius - 0.75f32.sqrt()).abs() < 1e-5, "{radius}"),
            // Loop rounds the corners in (its box faces are split at the seams, then welded).
            _ => assert!(radius < 0.75f32.sqrt() - 0.05, "{radius}"),
        }
    }
}

#[test]
fn fetch_without_the_registry_tools_fails_before_writing() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let cache = temp_dir("fetch_no_tools").join("cache");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(["assets", "fetch", "--cache", cache.to_str().unwrap()])
        .env("PATH", "")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.starts_with("error: `apt-get` not found on PATH: "),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(!cache.exists(), "the cache folder was created");
}

#[test]
fn fetch_rejects_an_unknown_group() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let out = penumbra(&["assets", "fetch", "--group", "statues"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("invalid value 'statues'"));
}

#[test]
fn committed_scene_files_state_their_triangles_and_resolve_through_the_cache() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
                             // Parse every scene in scenes/ with an empty cache: the seed scenes must fail only because
                             // the cache is empty (the message names the fetch), the others must load with their count.
    let cache = temp_dir("scenes_empty_cache");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("scenes");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        seen += 1;
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.lines().any(|l| l.starts_with("triangles = ")),
            "{}: no `triangles = N`",
            path.display()
        );
        match Scene::load_in(path.to_str().unwrap(), &[], Some(&cache)) {
            Ok(s) => assert!(s.triangle_count() > 0),
            Err(e) => {
                let e = penumbra_lab::cli_words(&e);
                assert!(text.contains("cache:"), "{}: {e}", path.display());
                assert!(
                    e.contains("penumbra assets fetch --group"),
                    "{}: {e}",
                    path.display()
                );
            }
        }
    }
    assert!(seen >= 10, "only {seen} scene files");
}

#[test]
fn an_open_mesh_under_back_face_culling_is_warned_about_once() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
                             // The one-triangle OFF is open (3 boundary edges); a tetrahedron wound outwards is closed.
    const TETRA_OFF: &str =
        "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    let dir = temp_dir("scene_open_mesh");
    std::fs::write(dir.join("tri.off"), TRI_OFF).unwrap();
    std::fs::write(dir.join("tetra.off"), TETRA_OFF).unwrap();
    let run = |mesh: &str, sets: &[&str]| {
        let scene = dir.join("scene.toml");
        std::fs::write(&scene, format!("{HEAD}\n[[mesh]]\nbuiltin = \"plane\"\nscale = [10.0, 1.0, 10.0]\n\n[[mesh]]\nfile = \"{mesh}\"\ntranslate = [0.0, 1.0, 0.0]\n")).unwrap();
        let out = dir.join("out");
        let _ = std::fs::remove_dir_all(&out);
        let mut args = vec![
            "render",
            "--scene",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(sets);
        let o = penumbra(&args);
        let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{stderr}");
        stderr
            .lines()
            .filter(|l| l.starts_with("warning:") && l.contains("is open"))
            .map(String::from)
            .collect::<Vec<_>>()
    };
    let open = run("tri.off", &[]);
    assert_eq!(open.len(), 1, "{open:?}");
    assert!(
        open[0].contains("mesh 2 (tri.off) is open (3 boundary edges)")
            && open[0].contains("cull = \"none\""),
        "{}",
        open[0]
    );
    // The ground plane (a built-in, open by design) is not named; nor is anything without culling
    // or a closed mesh.
    assert!(run("tri.off", &["--set", "cull=none"]).is_empty());
    assert!(run("tetra.off", &[]).is_empty());
    // The engine prints none of it: the line the binary printed is the loaded scene's warning.
    let open_again = run("tri.off", &[]);
    let scene = Scene::load(dir.join("scene.toml").to_str().unwrap(), &[]).unwrap();
    assert_eq!(scene.warnings, open_again, "{:?}", scene.warnings);
}
