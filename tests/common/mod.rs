//! Helpers shared by integration tests.
#![allow(dead_code)]

use penumbra::gpu::GpuContext;
use std::path::PathBuf;
use std::process::{Command, Output};

/// The GPU context; a missing adapter fails the test with instructions, never skips it.
pub fn gpu() -> GpuContext {
    match GpuContext::new() {
        Ok(ctx) => ctx,
        Err(e) => panic!("GPU test needs an adapter: {e}"),
    }
}

pub fn penumbra(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(args)
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .expect("run penumbra binary")
}

/// A fresh temporary folder under the target dir.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
