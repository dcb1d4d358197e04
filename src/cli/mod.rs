//! The commands of the binary, one file per command: its flags (clap) and the function that
//! turns them into the library's job, runs it and prints what it wrote. `main.rs` holds only the
//! command list, the global flags and the dispatch.

pub mod assets;
pub mod bench;
pub mod check;
pub mod compare;
pub mod environment;
pub mod failures;
pub mod framing;
pub mod hybrid;
pub mod info;
pub mod merge;
pub mod methods;
pub mod reference;
pub mod run_args;
pub mod render;
pub mod report;
pub mod scenes;
pub mod sequence;
pub mod sweep;

use anyhow::{Context, Result};

/// Parses a text flag (a scene name or path) from the raw argument, so a value that is not UTF-8 is
/// an error naming its flag, not clap's usage block.
pub fn utf8() -> impl clap::builder::TypedValueParser<Value = String> {
    use clap::builder::TypedValueParser;
    clap::builder::OsStringValueParser::new().try_map(|s| s.into_string().map_err(|s| format!("not valid UTF-8: {}", s.to_string_lossy())))
}

/// What `penumbra` with no arguments compares (docs/method.md: the seed's method, the project's
/// recommended preset, and the regular grids they are measured against; docs/methods.md: one of
/// each single-map family, hard, PCF, PCSS and a moment map).
pub const DEFAULT_METHODS: &str = "hard,pcf:kernel=poisson,pcss,msm,regular:n=5,layout=centred,regular:n=17,adaptive:preset=seed,adaptive:preset=balanced";

/// Splits `--set` pairs into render settings and method parameters.
pub fn split_sets(sets: &[String]) -> Result<(Vec<(String, String)>, Vec<(String, String)>)> {
    let (mut render, mut method) = (Vec::new(), Vec::new());
    for s in sets {
        let (k, v) = s.split_once('=').with_context(|| format!("--set {s}: expected KEY=VALUE"))?;
        let pair = (k.trim().to_string(), v.trim().to_string());
        if penumbra::methods::is_method_key(&pair.0) {
            method.push(pair);
        } else {
            render.push(pair);
        }
    }
    Ok((render, method))
}

/// Render settings from `--set`; method parameters belong in the method specs here.
pub fn render_sets(sets: &[String]) -> Result<Vec<(String, String)>> {
    let (render, method) = split_sets(sets)?;
    if let Some((k, _)) = method.first() {
        anyhow::bail!("--set {k}=...: method parameters go in the method spec, e.g. `adaptive:{k}=...`");
    }
    Ok(render)
}
