//! Benchmark suites run by `penumbra bench`: whole frames, side by side, on real scenes.
//! (Per-stage micro-benchmarks live in benches/, run with criterion.)

pub mod command;
pub(crate) mod errors;
pub mod fair;
pub(crate) mod seed;
pub(crate) mod suite;
pub mod table;

pub use suite::{prepare, run_seed_table2, SceneResult, SuiteOptions, SuiteResults, SuiteScene};

/// Suites `--suite` accepts.
pub const SUITES: &[&str] = &["seed-table2"];
