//! The flags every study shares, declared once and flattened into each command's arguments
//! (`#[command(flatten)]`), each with its one parser and one check: `--scene`, `--set`, `--out`,
//! `--repeats`. A command whose default differs says so on its own struct, e.g.
//! `#[command(mut_arg("out", |a| a.default_value("penumbra-out/cascades")))]`.

use crate::record::output_set;
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// `--scene`: one scene, built-in name or TOML path.
#[derive(clap::Args, Debug, Clone)]
pub struct SceneArgs {
    /// Built-in scene name or path to a scene TOML file.
    #[arg(long, default_value = "default", value_parser = utf8())]
    pub scene: String,
}

/// `--set KEY=VALUE`, repeatable: render settings for every scene the command loads.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct SetArgs {
    /// Override a render setting (the scene's `[render]` table), e.g. `--set resolution=256`;
    /// method parameters go in the method spec.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

impl SetArgs {
    /// The render settings; a method's parameter is refused with where it goes.
    pub fn render(&self) -> Result<Vec<(String, String)>> {
        render_sets(&self.set)
    }
}

/// `--out`: the folder the command writes its output set to.
#[derive(clap::Args, Debug, Clone)]
pub struct OutArgs {
    /// Output folder.
    #[arg(long, default_value = "penumbra-out")]
    pub out: PathBuf,
}

impl OutArgs {
    /// The folder, checked before anything runs: a file there, or a folder that cannot be made,
    /// is refused now, not after the run.
    pub fn checked(&self) -> Result<&Path> {
        output_set::check(&self.out)?;
        Ok(&self.out)
    }
}

/// `--repeats`: timed frames per setting; the median is quoted.
#[derive(clap::Args, Debug, Clone)]
pub struct RepeatsArgs {
    /// Timed frames per method after one warm-up (and one stages-mode frame); the median is quoted.
    #[arg(long, default_value_t = 3)]
    pub repeats: u32,
}

impl RepeatsArgs {
    /// The count, in 1..=1000.
    pub fn checked(&self) -> Result<u32> {
        repeats_in_range("--repeats", self.repeats)
    }
}

/// A count of timed frames for `flag`, in 1..=1000: past that a run is hours of the same frame.
pub fn repeats_in_range(flag: &str, n: u32) -> Result<u32> {
    if n == 0 || n > 1000 {
        anyhow::bail!("{flag} must be in 1..=1000, got {n}");
    }
    Ok(n)
}

/// Parses a text flag (a scene name or path) from the raw argument, so a value that is not UTF-8 is
/// an error naming its flag, not clap's usage block.
pub fn utf8() -> impl clap::builder::TypedValueParser<Value = String> {
    use clap::builder::TypedValueParser;
    clap::builder::OsStringValueParser::new().try_map(|s| {
        s.into_string()
            .map_err(|s| format!("not valid UTF-8: {}", s.to_string_lossy()))
    })
}

/// `--set` pairs: render settings only, in every command (`cull=none` is the shadow raster's
/// culling, never adaptive's `cull=on|off`). A key that only a method knows gets a line saying where
/// it goes; `param_flag` names the command's own flag for its method's parameters, if it has one.
pub fn render_sets_or(
    sets: &[String],
    method: Option<&str>,
    param_flag: Option<&str>,
) -> Result<Vec<(String, String)>> {
    let mut render = Vec::new();
    for s in sets {
        let (k, v) = s
            .split_once('=')
            .with_context(|| format!("--set {s}: expected KEY=VALUE"))?;
        let (k, v) = (k.trim(), v.trim());
        let short = k.strip_prefix("render.").unwrap_or(k);
        let owners = crate::methods::methods_with_param(short);
        if !crate::scene::is_render_key(short) && !owners.is_empty() {
            // The command's own method first, when it has the key.
            let owner = method.filter(|m| owners.contains(m)).unwrap_or(owners[0]);
            let noun = if owners.len() == 1 {
                format!("method {owner}")
            } else {
                format!("methods {}", owners.join(", "))
            };
            let flag = param_flag
                .map(|f| format!(" or {f} {short}={v}"))
                .unwrap_or_default();
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
            let (k, v) = s
                .split_once('=')
                .with_context(|| format!("--param {s}: expected KEY=VALUE"))?;
            Ok((k.trim().to_string(), v.trim().to_string()))
        })
        .collect()
}

/// `--certify K` and `--delta δ` (render, compare, frontier): the certificate's options, checked
/// before the GPU starts against what the scene allows; None without `--certify`.
pub fn certify_options(
    certify: Option<usize>,
    delta: Option<f64>,
    scene: &crate::scene::Scene,
) -> Result<Option<crate::certify::Options>> {
    let Some(pixels) = certify else {
        if let Some(d) = delta {
            anyhow::bail!("--delta {d}: needs --certify K (delta is the certified bound's confidence, 1 − delta)");
        }
        return Ok(None);
    };
    let options = crate::certify::Options {
        pixels,
        delta: delta.unwrap_or(crate::certify::DEFAULT_DELTA),
        ..Default::default()
    };
    let frame = scene.render.width as usize * scene.render.height as usize;
    match options.check(frame) {
        Err(crate::certify::OptionsError::NoPixels) => anyhow::bail!("--certify 0: draw at least one pixel (K pixels get the exact truth; 2048 is auto's default)"),
        Err(crate::certify::OptionsError::MorePixelsThanGeometry { .. }) => {
            anyhow::bail!("--certify {pixels}: more than the frame's {frame} pixels ({}x{})", scene.render.width, scene.render.height)
        }
        Err(crate::certify::OptionsError::Delta(d)) => anyhow::bail!("--delta {d}: outside (0, 1): the certified bound holds with probability 1 − delta"),
        Ok(()) => {}
    }
    if let Some(why) = crate::certify::truth::unsupported(scene) {
        anyhow::bail!("--certify {pixels}: scene {}: {why}", scene.origin);
    }
    Ok(Some(options))
}

/// The frame's geometry pixels against `--certify K`, once the frame says how many it has.
pub fn certify_fits(options: &crate::certify::Options, geometry: usize) -> Result<()> {
    if options.pixels > geometry {
        anyhow::bail!(
            "--certify {}: more than the frame's {geometry} geometry pixels",
            options.pixels
        );
    }
    Ok(())
}
