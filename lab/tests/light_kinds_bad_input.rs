//! `[light]` by kind (docs/lights.md): each kind loads, and every bad key is one line naming the
//! file, the key and the value. The methods that sample the rectangle refuse the other kinds by
//! name, before anything is written. Library checks need no GPU.

#[macro_use]
mod common;
use penumbra::research::methods::{Method, REGISTRY};
use penumbra::research::scene::{Emitter, LightKind, Scene};

const HEAD: &str = concat!(
    unlit_scene_head!(),
    r#"
[[mesh]]
builtin = "plane"
scale = 10.0

[[mesh]]
builtin = "box"
translate = [0.0, 1.0, 0.0]
"#
);

const DISK: &str =
    "kind = \"disk\"\ncenter = [0.0, 8.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\nradius = 1.0\n";
const SUN: &str = "kind = \"sun\"\ndirection = [0.3, -1.0, 0.2]\nangular_diameter_deg = 2.0\n";
const SPOT: &str = "kind = \"spot\"\nposition = [0.0, 8.0, 0.0]\ndirection = [0.0, -1.0, 0.0]\ninner_cone_deg = 20.0\nouter_cone_deg = 35.0\nradius = 0.5\n";
const POINT: &str = "kind = \"point\"\nposition = [0.0, 8.0, 0.0]\nradius = 0.5\n";

fn text(light: &str) -> String {
    format!("[light]\n{light}{HEAD}")
}

fn parse(light: &str) -> penumbra::Result<Scene> {
    Scene::parse(&text(light), "bad.toml", None, &[])
}

/// `light` with `from` replaced by `to`, refused: the message.
fn refused(light: &str, from: &str, to: &str) -> String {
    let changed = light.replacen(from, to, 1);
    assert_ne!(changed, light, "`{from}` is not in the light");
    let e = parse(&changed)
        .expect_err(&format!("`{to}` should be refused"))
        .to_string();
    assert!(!e.contains('\n'), "not one line: {e}");
    e
}

#[test]
fn each_kind_loads_with_its_shape() {
    let s = parse(DISK).unwrap();
    assert_eq!(
        s.emitter,
        Emitter::Disk(penumbra::research::scene::DiskLight {
            center: glam::Vec3::new(0.0, 8.0, 0.0),
            normal: glam::Vec3::NEG_Y,
            radius: 1.0
        })
    );
    let Emitter::Sun(sun) = parse(SUN).unwrap().emitter else {
        panic!("not a sun")
    };
    assert!(
        (sun.direction.length() - 1.0).abs() < 1e-6
            && sun.direction.y < 0.0
            && sun.angular_diameter_deg == 2.0
    );
    assert_eq!(parse(SPOT).unwrap().emitter.kind(), LightKind::Spot);
    assert_eq!(parse(POINT).unwrap().emitter.kind(), LightKind::Point);
    // No `kind`: the rectangle, as before.
    let rect =
        parse("center = [0.0, 8.0, 0.0]\nedge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 2.0]\n")
            .unwrap();
    assert_eq!(rect.emitter, Emitter::Rect);
    assert_eq!(rect.light.center, glam::Vec3::new(0.0, 8.0, 0.0));
    let rect = parse(
        "kind = \"rect\"\ncenter = [0.0, 8.0, 0.0]\nsize = [2.0, 2.0]\nnormal = [0.0, -1.0, 0.0]\n",
    )
    .unwrap();
    assert_eq!(rect.light.area(), 4.0);
}

#[test]
fn an_unknown_kind_or_a_wrong_type_names_the_line_and_the_value() {
    let e = refused(POINT, "kind = \"point\"", "kind = \"cone\"");
    assert_eq!(e, "bad.toml: at line 2, column 8: [light] kind = \"cone\": unknown variant `cone`, expected one of `rect`, `disk`, `sun`, `spot`, `point`");
    let e = refused(DISK, "radius = 1.0", "radius = \"big\"");
    assert_eq!(e, "bad.toml: at line 5, column 10: [light] radius = \"big\": invalid type: string \"big\", expected f32");
    let e = refused(
        SUN,
        "direction = [0.3, -1.0, 0.2]",
        "direction = [0.3, -1.0]",
    );
    assert!(
        e.starts_with("bad.toml: at line 3, column 13: [light] direction = [0.3, -1.0]: "),
        "{e}"
    );
}

#[test]
fn a_missing_key_names_it_and_the_kinds_keys() {
    let e = refused(DISK, "radius = 1.0\n", "");
    assert_eq!(
        e,
        "bad.toml: light.radius is missing: kind `disk` needs center, normal, radius"
    );
    let e = refused(SUN, "angular_diameter_deg = 2.0\n", "");
    assert_eq!(e, "bad.toml: light.angular_diameter_deg is missing: kind `sun` needs direction, angular_diameter_deg");
    let e = refused(SPOT, "outer_cone_deg = 35.0\n", "");
    assert_eq!(e, "bad.toml: light.outer_cone_deg is missing: kind `spot` needs position, direction, inner_cone_deg, outer_cone_deg, radius");
    let e = refused(POINT, "position = [0.0, 8.0, 0.0]\n", "");
    assert_eq!(
        e,
        "bad.toml: light.position is missing: kind `point` needs position, radius"
    );
    let e = parse("edge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 2.0]\n")
        .unwrap_err()
        .to_string();
    assert_eq!(e, "bad.toml: light.center is missing: kind `rect` needs center, and edge_u + edge_v or size + normal");
}

#[test]
fn a_key_of_another_kind_is_refused_naming_its_owners() {
    let e = refused(
        SUN,
        "angular_diameter_deg = 2.0\n",
        "angular_diameter_deg = 2.0\nradius = 1.0\n",
    );
    assert_eq!(e, "bad.toml: light.radius is not a key of kind `sun` (its keys: direction, angular_diameter_deg); it belongs to kind disk, spot, point");
    let e = refused(
        POINT,
        "radius = 0.5\n",
        "radius = 0.5\nedge_u = [1.0, 0.0, 0.0]\n",
    );
    assert_eq!(e, "bad.toml: light.edge_u is not a key of kind `point` (its keys: position, radius); it belongs to kind rect");
    // No `kind` is a rectangle: a disk's radius there says which kinds take it.
    let e = parse("center = [0.0, 8.0, 0.0]\nedge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 2.0]\nradius = 1.0\n").unwrap_err().to_string();
    assert_eq!(e, "bad.toml: light.radius is not a key of kind `rect` (its keys: center, edge_u, edge_v, size, normal, u_axis); it belongs to kind disk, spot, point");
}

#[test]
fn non_finite_numbers_are_refused_by_key_and_value() {
    let e = refused(DISK, "radius = 1.0", "radius = nan");
    assert_eq!(e, "bad.toml: light.radius = NaN: must be a finite number");
    let e = refused(
        SUN,
        "angular_diameter_deg = 2.0",
        "angular_diameter_deg = inf",
    );
    assert_eq!(
        e,
        "bad.toml: light.angular_diameter_deg = inf: must be a finite number"
    );
    let e = refused(SPOT, "inner_cone_deg = 20.0", "inner_cone_deg = -inf");
    assert_eq!(
        e,
        "bad.toml: light.inner_cone_deg = -inf: must be a finite number"
    );
    let e = refused(
        POINT,
        "position = [0.0, 8.0, 0.0]",
        "position = [0.0, nan, 0.0]",
    );
    assert_eq!(
        e,
        "bad.toml: light.position has a NaN or infinite coordinate: [0.0, NaN, 0.0]"
    );
    let e = refused(
        SPOT,
        "position = [0.0, 8.0, 0.0]",
        "position = [0.0, 8.0, 1e20]",
    );
    assert_eq!(e, "bad.toml: light.position = [0.0, 8.0, 1e20]: coordinates must be within ±1e6 (f32 has no precision left beyond)");
}

#[test]
fn sizes_directions_and_angles_out_of_range_are_refused() {
    for (light, from, to, want) in [
        (DISK, "radius = 1.0", "radius = 0.0", "light.radius = 0: must be positive and at most 1e6 (a soft shadow needs an emitter of some size)"),
        (POINT, "radius = 0.5", "radius = -2.0", "light.radius = -2: must be positive and at most 1e6 (a soft shadow needs an emitter of some size)"),
        (SPOT, "radius = 0.5", "radius = 1e9", "light.radius = 1000000000: must be positive and at most 1e6 (a soft shadow needs an emitter of some size)"),
        (DISK, "normal = [0.0, -1.0, 0.0]", "normal = [0.0, 0.0, 0.0]", "light.normal = [0.0, 0.0, 0.0]: has no direction (the zero vector)"),
        (SUN, "direction = [0.3, -1.0, 0.2]", "direction = [0.0, 0.0, 0.0]", "light.direction = [0.0, 0.0, 0.0]: has no direction (the zero vector)"),
        (SPOT, "direction = [0.0, -1.0, 0.0]", "direction = [0.0, 0.0, 0.0]", "light.direction = [0.0, 0.0, 0.0]: has no direction (the zero vector)"),
        (SUN, "angular_diameter_deg = 2.0", "angular_diameter_deg = 0.0", "light.angular_diameter_deg = 0: must be in (0, 30] degrees (the sun is 0.53; a sun of no size is a hard shadow, wider is a sky)"),
        (SUN, "angular_diameter_deg = 2.0", "angular_diameter_deg = 31.0", "light.angular_diameter_deg = 31: must be in (0, 30] degrees (the sun is 0.53; a sun of no size is a hard shadow, wider is a sky)"),
        (SPOT, "inner_cone_deg = 20.0", "inner_cone_deg = 40.0", "light.inner_cone_deg = 40 is wider than light.outer_cone_deg = 35: the inner cone lies inside the outer one"),
        (SPOT, "outer_cone_deg = 35.0", "outer_cone_deg = 90.0", "light.outer_cone_deg = 90: must be in (0, 90) degrees (a half-angle from the spot's direction)"),
        (SPOT, "outer_cone_deg = 35.0", "outer_cone_deg = 0.0", "light.outer_cone_deg = 0: must be in (0, 90) degrees (a half-angle from the spot's direction)"),
        (SPOT, "inner_cone_deg = 20.0", "inner_cone_deg = -5.0", "light.inner_cone_deg = -5: must be in [0, 90) degrees (a half-angle from the spot's direction)"),
    ] {
        assert_eq!(refused(light, from, to), format!("bad.toml: {want}"), "{to}");
    }
}

#[test]
fn a_disk_or_spot_turned_away_from_every_mesh_is_refused() {
    let e = refused(
        DISK,
        "normal = [0.0, -1.0, 0.0]",
        "normal = [0.0, 1.0, 0.0]",
    );
    assert_eq!(e, "bad.toml: light: the disk emits along light.normal = [0.0, 1.0, 0.0], away from every mesh: nothing would be lit; turn it towards the meshes");
    let e = refused(
        SPOT,
        "direction = [0.0, -1.0, 0.0]",
        "direction = [0.0, 2.0, 0.0]",
    );
    assert_eq!(e, "bad.toml: light: the spot points along light.direction = [0.0, 1.0, 0.0], away from every mesh: nothing would be lit; turn it towards the meshes");
}

/// The pairs docs/lights.md lists: `yes`, or the reason the method gives.
fn documented_pairs() -> Vec<(String, Vec<String>)> {
    let doc =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/lights.md")).unwrap();
    let table = doc
        .split("<!-- pairs -->")
        .nth(1)
        .expect("docs/lights.md has the pairs table between `<!-- pairs -->` marks");
    table
        .lines()
        .filter(|l| l.starts_with("| `"))
        .map(|l| {
            let cells: Vec<String> = l
                .trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_string())
                .collect();
            (cells[0].trim_matches('`').to_string(), cells[1..].to_vec())
        })
        .collect()
}

#[test]
fn the_methods_refuse_the_kinds_they_cannot_sample_as_docs_lights_md_lists() {
    let scenes: Vec<Scene> = [DISK, SUN, SPOT, POINT]
        .iter()
        .map(|l| parse(l).unwrap())
        .collect();
    let rect = Scene::parse(
        &text("center = [0.0, 8.0, 0.0]\nedge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 2.0]\n"),
        "bad.toml",
        None,
        &[],
    )
    .unwrap();
    let doc = documented_pairs();
    assert_eq!(
        doc.len(),
        REGISTRY.len(),
        "one row per method: {:?}",
        doc.iter().map(|d| &d.0).collect::<Vec<_>>()
    );
    let reasons = [
        penumbra::research::methods::ON_A_RECTANGLE,
        penumbra::research::methods::FROM_THE_CENTRE,
        penumbra::research::methods::PCSS_RECTANGLE,
        penumbra::research::methods::cascades::SUN_ONLY,
        penumbra::research::methods::ONE_MAP_PER_POINT,
    ];
    let mut refused = 0;
    for info in REGISTRY {
        let m = Method::parse(info.name, &[]).unwrap();
        let row = &doc
            .iter()
            .find(|(n, _)| n == info.name)
            .unwrap_or_else(|| panic!("docs/lights.md has no row for {}", info.name))
            .1;
        // Every method but cascades (the sun alone) takes the rectangle.
        assert_eq!(
            m.check_light(&rect).is_ok(),
            info.name != "cascades",
            "{}: rect",
            info.name
        );
        for (scene, cell) in std::iter::once(&rect).chain(&scenes).zip(row) {
            let kind = scene.emitter.kind().name();
            match m.check_light(scene) {
                Ok(()) => assert_eq!(cell, "yes", "{} on {kind}", info.name),
                Err(e) => {
                    let e = e.to_string();
                    let why = reasons
                        .iter()
                        .find(|r| e.contains(*r))
                        .unwrap_or_else(|| panic!("{e}"));
                    assert_eq!(e, format!("{}: light kind `{kind}` is not supported yet ({why}); scene bad.toml (docs/lights.md lists the pairs)", info.name));
                    assert_eq!(cell, &format!("no: {why}"), "{} on {kind}", info.name);
                    refused += 1;
                }
            }
        }
    }
    // Refused: the filtered maps (five) on the point, which has cube maps; cascades on every kind
    // but the sun; regions on the sun and the point (its windows are perspective maps from points
    // on a rectangle, a disk or a spot's ball).
    assert_eq!(refused, 11);
}

#[test]
fn render_and_compare_refuse_a_pair_with_one_line_and_no_output() {
    let dir = common::temp_dir("light_kinds_refused");
    std::fs::write(dir.join("point.toml"), text(POINT)).unwrap();
    for args in [
        &[
            "render",
            "--scene",
            "point.toml",
            "--method",
            "vsm",
            "--out",
            "out",
        ][..],
        &[
            "compare",
            "--scene",
            "point.toml",
            "--methods",
            "esm,vsm",
            "--out",
            "out",
        ][..],
    ] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
            .current_dir(&dir)
            .args(args)
            .env("PENUMBRA_NO_PROGRESS", "1")
            .output()
            .unwrap();
        let e = String::from_utf8_lossy(&out.stderr).to_string();
        assert_eq!(out.status.code(), Some(1), "{args:?}: {e}");
        let errors: Vec<&str> = e.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(errors.len(), 1, "{e}");
        assert!(!e.contains("panicked"), "{e}");
        let want = if args[0] == "render" {
            "error: vsm: light kind `point` is not supported yet (its map looks from"
        } else {
            "error: esm: light kind `point` is not supported yet (its map looks from"
        };
        assert!(errors[0].starts_with(want), "{}", errors[0]);
        assert!(!dir.join("out").exists(), "{args:?}: output written");
    }
    // The example docs/lights.md §4 shows, on the built-in scene.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .current_dir(&dir)
        .args([
            "render",
            "--scene",
            "point-edge",
            "--method",
            "vsm",
            "--out",
            "out",
        ])
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .unwrap();
    let doc =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/lights.md")).unwrap();
    let shown = doc
        .lines()
        .map(str::trim)
        .find(|l| l.starts_with("error: vsm: light kind"))
        .expect("docs/lights.md shows the message");
    assert_eq!(String::from_utf8_lossy(&out.stderr).trim(), shown);
    assert!(!dir.join("out").exists());
}
