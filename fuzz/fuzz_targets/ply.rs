#![no_main]
//! `cargo +nightly fuzz run ply fuzz/seeds/ply` (docs/robustness.md): rejecting an input is fine,
//! a panic, hang or runaway allocation is a finding. PLY may be binary: the bytes go in as they are.
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = penumbra_lab::inputs::ply(data);
});
