//! Built-in scenes, embedded so `penumbra` runs with no files at hand.

pub const BUILTIN_SCENES: &[(&str, &str, &str)] = &[
    ("default", "the small Stanford bunny on a ground plane under a square light", include_str!("../../scenes/default.toml")),
    (
        "analytic-square",
        "thin square occluder parallel to the ground under a parallel square light (closed form, method.md §5)",
        include_str!("../../scenes/analytic-square.toml"),
    ),
];

pub fn builtin_source(name: &str) -> Option<&'static str> {
    BUILTIN_SCENES.iter().find(|(n, _, _)| *n == name).map(|(_, _, s)| *s)
}

pub fn builtin_names() -> Vec<&'static str> {
    BUILTIN_SCENES.iter().map(|(n, _, _)| *n).collect()
}
