//! Built-in scenes: every shipped scenes/*.toml and the mesh files beside it, embedded by build.rs so
//! that `--scene NAME` works from any folder (`cache:` meshes still come from the asset cache).

include!(concat!(env!("OUT_DIR"), "/embedded_scenes.rs"));

/// (name, TOML text) of every shipped scene, `default` first.
pub(crate) const BUILTIN_SCENES: &[(&str, &str)] = SCENE_FILES;

pub fn builtin_source(name: &str) -> Option<&'static str> {
    BUILTIN_SCENES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, s)| *s)
}

pub fn builtin_names() -> Vec<&'static str> {
    BUILTIN_SCENES.iter().map(|(n, _)| *n).collect()
}

/// An embedded mesh file (relative `file =` paths of built-in scenes).
pub(crate) fn embedded_mesh(file: &str) -> Option<&'static str> {
    MESH_FILES.iter().find(|(n, _)| *n == file).map(|(_, t)| *t)
}
