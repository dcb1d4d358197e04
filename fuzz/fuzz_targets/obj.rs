#![no_main]
//! `cargo +nightly fuzz run obj fuzz/seeds/obj` (docs/robustness.md): rejecting an input is fine,
//! a panic, hang or runaway allocation is a finding.
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = penumbra_lab::inputs::obj(text);
    }
});
