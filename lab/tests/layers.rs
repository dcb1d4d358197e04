//! The lab's layers, lowest first, and the imports that run back up them. Data flows one way
//! (docs/architecture.md): a module may use the layers below it; an import of a higher layer is
//! listed here by file and counted, and the count may only fall. The engine's modules, which the
//! lab re-exports (`crate::gpu`, `crate::scene`, …), lie below every layer of the lab. Needs no GPU.

mod common;

/// Top-level modules of lab/src/, lowest layer first (the engine's re-exported modules first).
const LAYERS: &[&str] = &[
    "gpu",
    "scene",
    "render",
    "stages",
    "methods",
    "frame",
    "api",
    "error",
    "progress",
    "interrupt",
    "panic_log",
    "assets",
    "reference",
    "metrics",
    "record",
    "report",
    "studies",
    "inputs",
];

/// Imports that run back up today, at most: the error type wraps the errors of higher layers
/// (`#[from]`), and the record writes the report beside its rows. Lower it when one goes.
const MOST_UPWARD: usize = 5;

#[test]
fn imports_run_down_the_layers_but_for_a_known_few() {
    let up = common::layers::upward_imports(
        &common::root().join("lab/src"),
        LAYERS,
        &["main", "cli", "lib"],
    );
    for (file, target) in &up {
        println!("lab/src/{file} uses {target}");
    }
    println!("{} imports run back up the layers", up.len());
    assert!(
        up.len() <= MOST_UPWARD,
        "{} imports run back up (at most {MOST_UPWARD}): {up:#?}",
        up.len()
    );
}
