//! Studies: each runs methods over scenes and settings and writes a set of results (rows, charts,
//! a report): compare and sweep, the benchmark suites, the framing, hybrid-map and cascade studies,
//! sequences, the failure gallery, sharded sweeps and the environment study.

pub mod bench;
pub mod calibration;
pub mod cascades;
pub mod compare;
pub mod environment;
pub mod estimate;
pub mod failures;
pub mod framing;
pub mod frontier;
pub mod hybrid;
pub mod lists;
pub mod seams;
pub mod sequence;
pub mod shard;
