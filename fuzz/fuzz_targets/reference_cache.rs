#![no_main]
//! `cargo +nightly fuzz run reference_cache fuzz/seeds/reference_cache` (docs/robustness.md):
//! rejecting an input is fine, a panic, hang or runaway allocation is a finding. Each input is
//! read as given and resealed (its digest recomputed), which reaches the size and value checks.
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = penumbra_lab::inputs::reference_cache(data);
    let _ = penumbra_lab::inputs::reference_cache_resealed(data);
});
