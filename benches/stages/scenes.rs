//! Synthetic scenes for the benches: built-in meshes only, so `cargo bench` needs no asset fetch.

use penumbra::research::scene::Scene;

const HEAD: &str = r#"
[camera]
eye = [0.0, 9.0, 12.0]
target = [0.0, 0.5, 0.0]
fov_y_deg = 45.0

[light]
center = [2.0, 10.0, 1.0]
edge_u = [2.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 2.0]

[render]
width = 512
height = 512
shadow_map_size = 512

[[mesh]]
builtin = "plane"
scale = 16.0
"#;

/// Spheres on a ground plane: `segments` sets each sphere's triangles (s·(2s−2)), `count` the grid.
pub fn spheres(segments: u32, count: [u32; 2]) -> Scene {
    let text = format!(
        "{HEAD}\n[[mesh]]\nbuiltin = \"sphere\"\nsegments = {segments}\ntranslate = [0.0, 1.0, 0.0]\n\
         grid = {{ count = [{}, {}], spacing = [2.5, 2.5] }}\n",
        count[0], count[1]
    );
    Scene::parse(&text, "bench-spheres", None, &[]).expect("bench scene")
}

/// Shadow-raster workloads: about 10k, 100k and 1M triangles.
pub fn raster_scenes() -> Vec<Scene> {
    vec![
        spheres(72, [1, 1]),
        spheres(224, [1, 1]),
        spheres(224, [5, 2]),
    ]
}

/// The adaptive stages run on the embedded default scene (small bunny, 512x512, 512² maps): what
/// they cost depends on pixels and penumbrae, not on triangles.
pub fn stage_scene() -> Scene {
    Scene::load("default", &[]).expect("built-in scene")
}
