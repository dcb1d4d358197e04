//! Helpers shared by the lab's integration tests: the engine's (tests/common), and the runners of
//! the `penumbra` binary.
#![allow(dead_code)]

#[macro_use]
#[path = "../../../tests/common/mod.rs"]
mod engine;

pub use engine::*;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root: the fixtures (scenes/, sweeps/, fuzz/seeds, scripts/, docs/) live there.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("lab/ has a parent")
        .to_path_buf()
}

/// Runs the binary in the repository root, as `cargo run` there does (cargo runs the lab's tests
/// in lab/): its default paths (`--scenes scenes`, …) resolve as they do for a user.
pub fn penumbra(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .current_dir(root())
        .args(args)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .expect("run penumbra binary")
}

pub fn penumbra_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_penumbra"));
    c.current_dir(root())
        .args(args)
        .env("PENUMBRA_NO_PROGRESS", "1");
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run penumbra binary")
}
