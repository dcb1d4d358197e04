//! The engine's layers, lowest first, and the imports that run back up them. Data flows one way
//! (docs/architecture.md): a module may use the layers below it; an import of a higher layer is
//! listed here by file and counted, and the count may only fall. The engine cannot name the lab
//! (lab/): the compiler keeps that boundary. Needs no GPU.

mod common;

use std::path::Path;

/// Top-level modules of src/, lowest layer first.
const LAYERS: &[&str] = &[
    "error", "progress", "gpu", "scene", "render", "stages", "certify", "methods", "frame", "api",
];

#[test]
fn imports_run_down_the_layers_but_for_a_known_few() {
    let up = common::layers::upward_imports(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        LAYERS,
        &["lib"],
    );
    for (file, target) in &up {
        println!("src/{file} uses {target}");
    }
    println!("{} imports run back up the layers", up.len());
    // The engine has none left: every import runs down the layers.
    assert!(
        up.is_empty(),
        "{} imports run back up (none may): {up:#?}",
        up.len()
    );
}
