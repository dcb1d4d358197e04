// Records the git hash for run records ("unknown" outside a git checkout), and embeds every shipped
// scene (scenes/*.toml) and every mesh file beside them (scenes/*.obj), so scenes resolve by name
// from any folder.
use std::path::Path;

fn main() {
    let hash = std::process::Command::new("git")
        .args(["rev-parse", "--short=12", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=PENUMBRA_GIT_HASH={hash}");
    println!("cargo:rerun-if-changed=.git/HEAD");
    println!("cargo:rerun-if-changed=.git/refs/heads");
    embed_scenes();
}

fn embed_scenes() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("scenes/ folder")
        .map(|e| e.expect("scenes/ entry").path())
        .collect();
    // `default` first, then by name: the order `penumbra scenes` lists them in.
    files.sort_by_key(|p| {
        (
            p.file_stem().is_none_or(|s| s != "default"),
            p.file_name().map(|n| n.to_os_string()),
        )
    });
    let (mut scenes, mut meshes) = (String::new(), String::new());
    for path in &files {
        println!("cargo:rerun-if-changed={}", path.display());
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .expect("UTF-8 file name in scenes/");
        let entry = format!(
            "    ({:?}, include_str!({:?})),\n",
            name,
            path.display().to_string()
        );
        match path.extension().and_then(|e| e.to_str()) {
            Some("toml") => scenes.push_str(&entry.replacen(
                &format!("{name:?}"),
                &format!("{:?}", name.trim_end_matches(".toml")),
                1,
            )),
            Some("obj") => meshes.push_str(&entry),
            _ => {}
        }
    }
    let code = format!(
        "/// Every scenes/*.toml: (name, text).\npub(crate) const SCENE_FILES: &[(&str, &str)] = &[\n{scenes}];\n\
         /// Every scenes/*.obj: (file name, text).\npub(crate) const MESH_FILES: &[(&str, &str)] = &[\n{meshes}];\n"
    );
    let out = Path::new(&std::env::var("OUT_DIR").expect("OUT_DIR")).join("embedded_scenes.rs");
    std::fs::write(out, code).expect("write embedded_scenes.rs");
}
