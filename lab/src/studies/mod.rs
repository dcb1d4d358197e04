//! Studies: each runs methods over scenes and settings and writes a set of results (rows, charts,
//! a report): compare and sweep, the benchmark suites, the framing, hybrid-map and cascade studies,
//! sequences, the failure gallery, sharded sweeps and the environment study.
//!
//! One folder per study holds all of it: `command.rs` (its flags and the run that checks them,
//! runs and writes), the job itself (`mod.rs`), its files and its chart (`charts.rs`). The flags
//! every study shares are declared once, in `flags.rs`; the binary's command list
//! (lab/src/main.rs) names each study's arguments type on one line (docs/adding-a-study.md).

pub mod bench;
pub mod calibration;
pub mod cascades;
pub mod certify;
pub mod compare;
pub mod convergence;
pub mod environment;
pub mod estimate;
pub mod failures;
pub mod flags;
pub mod framing;
pub mod frontier;
pub mod hybrid;
pub mod lists;
pub mod oracle;
pub mod seams;
pub mod sequence;
pub mod shard;

/// A command of the binary: its flags as clap parses them, and the run that checks them (before
/// the GPU starts or anything is written), runs, and writes its output set.
pub trait Run {
    fn run(self, gpu: &crate::gpu::AdapterRequest) -> anyhow::Result<()>;
}
