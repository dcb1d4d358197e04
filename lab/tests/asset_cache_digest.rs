//! The asset cache is checked on read: a `cache:` mesh or panorama that the fetch pinned is used
//! only while its sha256 matches the pin (lab/src/assets/pinned.rs, docs/robustness.md). A
//! damaged or replaced file is one line naming it and the fetch that replaces it; a file of the
//! user's own under the cache has no pin and loads as before. No GPU.

#[macro_use]
mod common;
use common::temp_dir;
use penumbra::research::scene::{MeshDirs, Scene};
use std::path::Path;

/// One triangle, in OFF: not the pinned cow (182,966 bytes).
const TRI_OFF: &str = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 0 1\n3 0 2 1\n";

fn parse(text: &str, cache: &Path) -> penumbra::Result<Scene> {
    Scene::parse_in(
        text,
        "test.toml",
        MeshDirs {
            scene_dir: Some(cache),
            cache: Some(cache),
            max_mesh_bytes: None,
        },
        &[],
    )
}

fn mesh_scene(file: &str) -> String {
    format!(
        "{}\n[[mesh]]\nbuiltin = \"plane\"\nscale = 10.0\n\n[[mesh]]\nfile = \"{file}\"\n",
        tiny_scene_head!()
    )
}

#[test]
fn a_pinned_mesh_that_was_damaged_or_replaced_is_refused_naming_it() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let cache = temp_dir("asset_digest_mesh");
    std::fs::create_dir_all(cache.join("meshes")).unwrap();
    let cow = cache.join("meshes/cow.off");
    std::fs::write(&cow, TRI_OFF).unwrap();
    let expected = format!(
        "test.toml: mesh 2: file = \"cache:meshes/cow.off\": {} is not the file the asset cache pinned ({} bytes with sha256 {}; pinned: 182966 bytes with sha256 1c5a25c3047fc6b14dd0c962d3562b1796671422ab4634f9d46f9f23814cd54a): it was damaged or replaced; run `penumbra assets fetch --group meshes` to fetch it again",
        cow.display(),
        TRI_OFF.len(),
        sha256_hex(TRI_OFF.as_bytes())
    );
    assert_eq!(
        parse(&mesh_scene("cache:meshes/cow.off"), &cache)
            .unwrap_err()
            .to_string(),
        expected
    );
    // The same file by another spelling of its path is the same pinned file.
    let e = parse(&mesh_scene("cache:meshes/./cow.off"), &cache)
        .unwrap_err()
        .to_string();
    assert!(e.contains("is not the file the asset cache pinned"), "{e}");
    // A file the manifest does not pin is the user's own: it loads.
    std::fs::write(cache.join("meshes/mine.off"), TRI_OFF).unwrap();
    assert_eq!(
        parse(&mesh_scene("cache:meshes/mine.off"), &cache)
            .unwrap()
            .triangle_count(),
        3
    );
}

#[test]
fn a_pinned_panorama_that_was_damaged_is_refused_naming_it() {
    penumbra_lab::install(); // the asset layer: `cache:` paths and the registry mesh formats
    let cache = temp_dir("asset_digest_panorama");
    std::fs::create_dir_all(cache.join("panoramas")).unwrap();
    let city = cache.join("panoramas/city.exr");
    std::fs::write(&city, vec![0u8; 213_545]).unwrap(); // the pinned size, zeroed
    let text = "[camera]\neye = [0.0, 6.0, 8.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 45.0\n\n[environment]\npanorama = \"cache:panoramas/city.exr\"\n\n[[mesh]]\nbuiltin = \"plane\"\nscale = 10.0\n";
    let e = parse(text, &cache).unwrap_err().to_string();
    assert!(
        e.starts_with(&format!("test.toml: environment.panorama = `cache:panoramas/city.exr`: cache:panoramas/city.exr: {} is not the file the asset cache pinned (213545 bytes with sha256 ", city.display()))
            && e.ends_with("run `penumbra assets fetch --group panoramas` to fetch it again"),
        "{e}"
    );
}

fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}
