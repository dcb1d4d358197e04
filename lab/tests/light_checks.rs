//! Lights that enclose, cut or dwarf the scene, or a sun shining upward, are refused when the
//! scene loads, with one line naming the file, the key and the value (src/scene/light_checks.rs,
//! docs/lights.md §1). The shipped scenes pass. Library checks need no GPU.

#[macro_use]
mod common;
use penumbra::research::scene::light_checks::MAX_LIGHT_DIAGONALS;
use penumbra::research::scene::{builtin_names, Emitter, Scene};

/// A 30 × 30 ground (the builtin plane is one unit across) and a unit box on it (top at y = 1.5).
const MESHES: &str = concat!(
    unlit_scene_head!(),
    r#"
[[mesh]]
builtin = "plane"
scale = 30.0

[[mesh]]
builtin = "box"
translate = [0.0, 1.0, 0.0]
"#
);

fn parse(light: &str) -> penumbra::Result<Scene> {
    Scene::parse(&format!("[light]\n{light}{MESHES}"), "bad.toml", None, &[])
}

fn refused(light: &str) -> String {
    let e = parse(light).expect_err("should be refused").to_string();
    assert!(!e.contains('\n'), "not one line: {e}");
    e
}

#[test]
fn the_shipped_scenes_pass_and_their_lights_are_far_below_the_bound() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let mut loaded = 0;
    let mut widest = (0.0f32, "");
    for name in builtin_names() {
        // Scenes whose meshes come from the asset cache cannot load without it; every other must.
        let scene = match Scene::load(name, &[]) {
            Ok(s) => s,
            Err(e) if e.to_string().contains("not in the asset cache") => continue,
            Err(e) => panic!("{name}: {e}"),
        };
        loaded += 1;
        let across = match scene.emitter {
            Emitter::Rect => {
                (scene.light.edge_u.length_squared() + scene.light.edge_v.length_squared()).sqrt()
            }
            Emitter::Disk(d) => 2.0 * d.radius,
            Emitter::Spot(s) => 2.0 * s.radius,
            Emitter::Point(p) => 2.0 * p.radius,
            Emitter::Sun(s) => {
                assert!(s.direction.y < 0.0, "{name}");
                0.0
            }
        };
        if scene.environment.is_none() && across / scene.bounds.diagonal() > widest.0 {
            widest = (across / scene.bounds.diagonal(), name);
        }
    }
    let (widest, which) = widest;
    println!("{loaded} scenes loaded; the widest light is {which}'s, {widest:.3} of its scene's diagonal");
    assert!(loaded >= 10, "{loaded}");
    assert!(
        widest < 1.0 && widest * 10.0 < MAX_LIGHT_DIAGONALS,
        "{widest}"
    );
}

#[test]
fn a_sun_shining_upward_or_along_the_horizon_is_refused() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let sun = |d: &str| format!("kind = \"sun\"\ndirection = {d}\nangular_diameter_deg = 2.0\n");
    assert_eq!(
        refused(&sun("[0.0, 1.0, 0.0]")),
        "bad.toml: light.direction = [0.0, 1.0, 0.0]: the sun shines upward (direction is the way its light travels, from the sun to the scene, and +y is up): no surface that faces up would be lit; give it a negative y, e.g. [0.3, -1.0, 0.2]"
    );
    assert!(refused(&sun("[1.0, 0.0, 0.0]")).starts_with(
        "bad.toml: light.direction = [1.0, 0.0, 0.0]: the sun shines along the horizon "
    ));
    assert!(
        parse(&sun("[1.0, -0.05, 0.0]")).is_ok(),
        "a low sun is a sun"
    );
}

#[test]
fn a_sphere_around_the_camera_or_reaching_into_a_mesh_is_refused() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let point = |p: &str, r: f32| format!("kind = \"point\"\nposition = {p}\nradius = {r}\n");
    // Around the camera (and the whole scene): the camera is named.
    assert_eq!(
        refused(&point("[0.0, 2.0, 0.0]", 40.0)),
        "bad.toml: light.position = [0.0, 2.0, 0.0], light.radius = 40: the emitter's sphere encloses the camera (camera.eye = [0.0, 6.0, 8.0] is 8.944272 from its centre): the camera would look out from inside the light; move light.position away or shrink light.radius"
    );
    // Cutting the ground 0.5 below its centre.
    assert_eq!(
        refused(&point("[5.0, 0.5, 5.0]", 1.0)),
        "bad.toml: light.position = [5.0, 0.5, 5.0], light.radius = 1: the emitter's sphere reaches into mesh 1 (a triangle of it is 0.5 from the centre): points inside the emitter are unlit, so the figures would measure the sphere, not the shadows; move light.position clear of the meshes or shrink light.radius"
    );
    // Reaching into the box (top at y = 1.5) from above; a spot's sphere is checked the same way.
    let spot = "kind = \"spot\"\nposition = [0.0, 2.0, 0.0]\ndirection = [0.0, -1.0, 0.0]\ninner_cone_deg = 20.0\nouter_cone_deg = 35.0\nradius = 0.75\n";
    assert!(refused(spot).contains("light.radius = 0.75: the emitter's sphere reaches into mesh 2 (a triangle of it is 0.5 from the centre)"), "{}", refused(spot));
    // Clear of both by a hair: accepted.
    assert!(parse(&point("[5.0, 0.5, 5.0]", 0.49)).is_ok());
    assert!(parse(&spot.replace("radius = 0.75", "radius = 0.49")).is_ok());
}

#[test]
fn a_light_that_dwarfs_the_scene_is_refused() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
                             // The meshes' box is 30 × 1.5 × 30: diagonal 42.45, so the bound is 424.5 across. The disk
                             // is 100 up, where its angular size from the scene is within the maps' field up to radius 595.
    let disk = |r: &str| {
        format!("kind = \"disk\"\ncenter = [0.0, 100.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\nradius = {r}\n")
    };
    assert_eq!(
        refused(&disk("1e6")),
        "bad.toml: light.radius = 1000000: the light is 2e6 across, over 10 × the meshes' diagonal of 42.453 (424.529): it would light the scene as a sky, which the shadow maps fitted to the scene cannot see; shrink it (a light far away is kind = \"sun\")"
    );
    assert!(parse(&disk("200.0")).is_ok(), "400 across is within 424.5");
    assert!(refused(&disk("213.0"))
        .starts_with("bad.toml: light.radius = 213: the light is 426.000 across"));
    let rect = "center = [0.0, 8.0, 0.0]\nedge_u = [400.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 300.0]\n";
    assert!(refused(rect).starts_with("bad.toml: light.edge_u = [400.0, 0.0, 0.0], light.edge_v = [0.0, 0.0, 300.0] (or light.size): the light is 500.000 across"), "{}", refused(rect));
}

/// What breaks the maps is the light's angular size seen from the scene: the maps look from points
/// of the emitter at most tangent 6 (80.5°) off its normal. The meshes' middle is [0, 0.75, 0], 7.25
/// below a disk at height 8, so the boundary is a radius of 6 × 7.25 = 43.5 (within the 10-diagonal
/// bound of 212): 43 is accepted, 44 refused. A disk of radius 200 at height 8 gave `regular:n=3`
/// an RMSE of 0.87 before (results/bad-input-census/README.md measures the rise).
#[test]
fn a_light_too_wide_seen_from_the_scene_is_refused() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let disk = |r: &str| {
        format!(
            "kind = \"disk\"\ncenter = [0.0, 8.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\nradius = {r}\n"
        )
    };
    assert!(parse(&disk("43.0")).is_ok());
    assert_eq!(
        refused(&disk("44.0")),
        "bad.toml: light.center = [0.0, 8.0, 0.0], light.radius = 44: seen from the middle of the meshes' bounds ([0.0, 0.75, 0.0]) the light reaches 80.6° from its normal (tangent 6.07), past the 80.5° (tangent 6) its shadow maps see from each of its points: the maps from its outer part would not see the scene; make it smaller or move it farther from the meshes"
    );
    assert!(refused(&disk("200.0")).contains("light.radius = 200: seen from the middle of the meshes' bounds ([0.0, 0.75, 0.0]) the light reaches 87.9° from its normal (tangent 27.59)"), "{}", refused(&disk("200.0")));
    // A 290 × 290 rectangle 10 up; the same rectangle 40 up sees the scene within the maps' field.
    let rect = |h: f32| {
        format!("center = [0.0, {h:.1}, 0.0]\nsize = [290.0, 290.0]\nnormal = [0.0, -1.0, 0.0]\n")
    };
    assert!(refused(&rect(10.0)).starts_with("bad.toml: light.edge_u = [290.0, 0.0, 0.0], light.edge_v = [-0.0, 0.0, 290.0] (or light.size): seen from the middle of the meshes' bounds ([0.0, 0.75, 0.0]) the light reaches 86.3° from its normal (tangent 15.68)"), "{}", refused(&rect(10.0)));
    assert!(parse(&rect(40.0)).is_ok());
    // A spot's sphere is a disk across its axis: the same check.
    let spot = "kind = \"spot\"\nposition = [0.0, 3.0, 0.0]\ndirection = [0.0, -1.0, 0.0]\ninner_cone_deg = 20.0\nouter_cone_deg = 35.0\nradius = 1.4\n";
    assert!(parse(spot).is_ok());
    // The sun's maps are orthographic and the point's are cube faces: neither has the limit.
    assert!(parse("kind = \"point\"\nposition = [0.0, 2.5, 0.0]\nradius = 0.9\n").is_ok());
}

#[test]
fn a_disk_or_spot_turned_away_is_still_refused_by_the_same_checks() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let e = refused(
        "kind = \"disk\"\ncenter = [0.0, 8.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\nradius = 1.0\n",
    );
    assert_eq!(e, "bad.toml: light: the disk emits along light.normal = [0.0, 1.0, 0.0], away from every mesh: nothing would be lit; turn it towards the meshes");
}

/// Refused before any GPU work or output: one `error:` line, exit 1, `--out` never created.
#[test]
fn the_binary_refuses_before_rendering() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = common::temp_dir("light_checks_binary");
    let scene = dir.join("up.toml");
    std::fs::write(&scene, format!("[light]\nkind = \"sun\"\ndirection = [0.0, 1.0, 0.0]\nangular_diameter_deg = 0.53\n{MESHES}")).unwrap();
    let out = dir.join("out");
    for cmd in ["render", "compare", "reference"] {
        let o = common::penumbra(&[
            cmd,
            "--scene",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{cmd}: {err}");
        assert_eq!(err.lines().count(), 1, "{cmd}: {err}");
        assert!(
            err.starts_with(&format!(
                "error: {}: light.direction = [0.0, 1.0, 0.0]: the sun shines upward",
                scene.display()
            )),
            "{cmd}: {err}"
        );
        assert!(!out.exists(), "{cmd} wrote {}", out.display());
    }
}
