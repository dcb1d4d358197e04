//! Every shipped scene (scenes/*.toml) is built in: listed by `penumbra scenes` with its triangle
//! count, sources and asset state, and resolvable by name from any folder.

mod common;
use common::{penumbra, temp_dir};
use penumbra::research::scene::{builtin_names, builtin_source, catalog, Scene};
use std::path::Path;
use std::process::Command;

fn shipped() -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("scenes");
    let mut v: Vec<(String, String)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| {
            (
                p.file_stem().unwrap().to_string_lossy().to_string(),
                std::fs::read_to_string(&p).unwrap(),
            )
        })
        .collect();
    v.sort();
    v
}

#[test]
fn every_shipped_scene_is_embedded_with_its_text() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let files = shipped();
    assert!(files.len() >= 10, "only {} scene files found", files.len());
    let mut names = builtin_names();
    assert_eq!(names[0], "default");
    names.sort();
    assert_eq!(
        names,
        files.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>()
    );
    for (name, text) in &files {
        assert_eq!(
            builtin_source(name),
            Some(text.as_str()),
            "{name}: embedded text differs from scenes/{name}.toml"
        );
    }
}

#[test]
fn catalog_states_triangles_sources_and_missing_assets() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let empty = temp_dir("catalog_empty_cache");
    let entries = catalog(Some(&empty));
    assert_eq!(entries.len(), shipped().len());
    let get = |n: &str| entries.iter().find(|e| e.name == n).unwrap();
    let cows = get("cows");
    assert_eq!(cows.triangles, Some(208_946));
    assert_eq!(cows.sources, ["plane", "cache:meshes/cow.off"]);
    assert_eq!(cows.missing, [empty.join("meshes/cow.off")]);
    assert_eq!(
        penumbra_lab::assets::fetch_command(&cows.fetch_groups).as_deref(),
        Some("penumbra assets fetch --group meshes")
    );
    let default = get("default");
    assert_eq!(
        (
            default.triangles,
            default.missing.len(),
            default.fetch_groups.len()
        ),
        (Some(58_786), 0, 0)
    );
    assert_eq!(default.sources, ["plane", "embedded bunny-small.obj"]);
    assert_eq!(get("grove").fetch_groups, ["trees"]);
    // A cache holding the file: present.
    std::fs::create_dir_all(empty.join("meshes")).unwrap();
    std::fs::write(empty.join("meshes/cow.off"), "OFF\n0 0 0\n").unwrap();
    assert!(catalog(Some(&empty))
        .iter()
        .find(|e| e.name == "cows")
        .unwrap()
        .missing
        .is_empty());
}

#[test]
fn scenes_command_lists_every_scene_with_its_count_and_asset_state() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let cache = temp_dir("scenes_cmd_cache");
    let out = Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .arg("scenes")
        .env("PENUMBRA_CACHE", &cache)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    for (name, _) in shipped() {
        assert!(
            text.lines().any(|l| l.starts_with(&format!("{name} "))),
            "{name} not listed:\n{text}"
        );
    }
    let cows = text.lines().find(|l| l.starts_with("cows ")).unwrap();
    assert!(
        cows.contains("208946")
            && cows.contains("missing")
            && cows.contains("cache:meshes/cow.off"),
        "{cows}"
    );
    assert!(
        text.contains("fetch with `penumbra assets fetch --group meshes`"),
        "{text}"
    );
}

#[test]
fn a_cached_scene_with_a_missing_asset_stops_with_the_fetch_command() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let cache = temp_dir("byname_missing_cache");
    let e = Scene::load_in("cows", &[], Some(&cache)).unwrap_err();
    // The engine names the group in its own words; the command line says how to fetch it.
    let engine = e.to_string();
    assert!(
        engine.contains("cache:meshes/cow.off")
            && engine.ends_with("is missing; asset group `meshes`)")
            && !engine.contains("penumbra assets"),
        "{engine}"
    );
    let cli = penumbra_lab::cli_words(&e);
    assert!(
        cli.contains("cache:meshes/cow.off")
            && cli.contains("run `penumbra assets fetch --group meshes`"),
        "{cli}"
    );
}

#[test]
fn a_scene_with_an_embedded_relative_mesh_renders_by_name_outside_the_repository() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let dir = temp_dir("byname_outside");
    let out = Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .current_dir(&dir)
        .args([
            "render",
            "--scene",
            "default",
            "--method",
            "hard",
            "--set",
            "resolution=32",
            "--set",
            "shadow_map_size=64",
            "--out",
            "o",
        ])
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("o/run.json")).unwrap()).unwrap();
    assert_eq!(record["scene"], "default");
    // The same from the library: the bunny file comes from the binary, not from scenes/.
    let s = Scene::load("default", &[]).unwrap();
    assert_eq!(
        (s.origin.as_str(), s.triangle_count()),
        ("builtin:default", 58_786)
    );
}

#[test]
fn unknown_scene_name_lists_the_built_ins() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let out = penumbra(&["render", "--scene", "no-such-scene", "--out", "never"]);
    let e = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        e.contains("no-such-scene: no such scene file or built-in scene")
            && e.contains("cows")
            && e.contains("teapot"),
        "{e}"
    );
}
