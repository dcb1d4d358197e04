//! The commands of the binary that are not studies, one file per command: its flags (clap) and
//! its run. A study's command lives in its folder (lab/src/studies/<study>/command.rs). `main.rs`
//! holds the command list, the global flags and the dispatch.

pub mod assets;
pub mod check;
pub mod info;
pub mod methods;
pub mod parse;
pub mod reference;
pub mod render;
pub mod report;
pub mod scenes;
