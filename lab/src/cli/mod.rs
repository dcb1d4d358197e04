//! The commands of the binary, one file per command: its flags (clap) and the function that
//! turns them into the library's job, runs it and prints what it wrote. `main.rs` holds only the
//! command list, the global flags and the dispatch.

pub mod assets;
pub mod bench;
pub mod calibrate;
pub mod cascades;
pub mod check;
pub mod compare;
pub mod environment;
pub mod failures;
pub mod framing;
pub mod estimate;
pub mod frontier;
pub mod hybrid;
pub mod info;
pub mod merge;
pub mod methods;
pub mod parse;
pub mod reference;
pub mod run_args;
pub mod render;
pub mod report;
pub mod scenes;
pub mod seams;
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

/// `--set` pairs: render settings only, in every command (`cull=none` is the shadow raster's
/// culling, never adaptive's `cull=on|off`). A key that only a method knows gets a line saying where
/// it goes; `param_flag` names the command's own flag for its method's parameters, if it has one.
pub fn render_sets_or(sets: &[String], method: Option<&str>, param_flag: Option<&str>) -> Result<Vec<(String, String)>> {
    let mut render = Vec::new();
    for s in sets {
        let (k, v) = s.split_once('=').with_context(|| format!("--set {s}: expected KEY=VALUE"))?;
        let (k, v) = (k.trim(), v.trim());
        let short = k.strip_prefix("render.").unwrap_or(k);
        let owners = penumbra_lab::methods::methods_with_param(short);
        if !penumbra_lab::scene::is_render_key(short) && !owners.is_empty() {
            // The command's own method first, when it has the key.
            let owner = method.filter(|m| owners.contains(m)).unwrap_or(owners[0]);
            let noun = if owners.len() == 1 { format!("method {owner}") } else { format!("methods {}", owners.join(", ")) };
            let flag = param_flag.map(|f| format!(" or {f} {short}={v}")).unwrap_or_default();
            anyhow::bail!("--set {k}={v}: {short} is a parameter of {noun}, not a render setting; write it in the method spec ({owner}:{short}={v}){flag}");
        }
        render.push((k.to_string(), v.to_string()));
    }
    Ok(render)
}

/// Render settings from `--set`, for commands whose methods take parameters only in their specs.
pub fn render_sets(sets: &[String]) -> Result<Vec<(String, String)>> {
    render_sets_or(sets, None, None)
}

/// `--param KEY=VALUE` pairs for a command's one method.
pub fn param_pairs(params: &[String]) -> Result<Vec<(String, String)>> {
    params
        .iter()
        .map(|s| {
            let (k, v) = s.split_once('=').with_context(|| format!("--param {s}: expected KEY=VALUE"))?;
            Ok((k.trim().to_string(), v.trim().to_string()))
        })
        .collect()
}
