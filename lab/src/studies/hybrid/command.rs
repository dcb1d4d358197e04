//! `penumbra hybrid`: hybrid-resolution shadow maps (seed 003) against plain maps.

use super::render_sets;
use anyhow::{Context, Result};
use penumbra_lab::gpu::{AdapterRequest, GpuContext};
use penumbra_lab::record::{output_set, run_files};
use penumbra_lab::reference::truth;
use penumbra_lab::scene::Scene;
use penumbra_lab::studies::compare::methods_list;
use penumbra_lab::methods::Method;
use penumbra_lab::studies::hybrid::{self, parse_maps};
use penumbra_lab::studies::lists::listed_once;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct HybridArgs {
    /// Built-in scene name or path to a scene TOML file.
    #[arg(long, default_value = "default", value_parser = crate::cli::utf8())]
    scene: String,
    /// Square screen size in pixels.
    #[arg(long, default_value_t = 256)]
    resolution: u32,
    /// Plain map sizes of the hard-shadow part, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "512,1024,2048,4096")]
    plain: Vec<String>,
    /// Hybrid maps of the hard-shadow part as BASE/LEVELS, comma-separated (2048/2 is 2048 → 512).
    #[arg(long, value_delimiter = ',', default_value = "1024/1,2048/1,2048/2,4096/2")]
    hybrid: Vec<String>,
    /// Merge tolerance in 16-bit depth units (the seed's 0.25).
    #[arg(long, default_value_t = 0.25)]
    eps: f32,
    /// Timed hard-shadow frames per configuration after a warm-up and a stages-mode frame.
    #[arg(long, default_value_t = 3)]
    repeats: u32,
    /// Multi-map methods (comma-separated; empty for none), e.g. `regular:n=17,adaptive:preset=balanced`.
    #[arg(long, value_delimiter = ',', default_value = "")]
    multi: Vec<String>,
    /// The multi-map methods' hybrid maps, BASE/LEVELS.
    #[arg(long, default_value = "2048/2")]
    multi_hybrid: String,
    /// Plain sizes the multi-map methods also run with (the size of equal memory is added).
    #[arg(long, value_delimiter = ',', default_value = "512")]
    multi_plain: Vec<String>,
    /// Timed multi-map frames per configuration after one stages-mode frame (no warm-up: slow scenes).
    #[arg(long, default_value_t = 1)]
    multi_repeats: u32,
    /// Override a render setting, e.g. `--set shadow_map_budget_mib=1024`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    #[arg(long, default_value = "penumbra-out/hybrid")]
    out: PathBuf,
}

pub fn run(args: HybridArgs, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&args.out)?;
    if !(8..=4096).contains(&args.resolution) {
        anyhow::bail!("--resolution: {} is not in 8..=4096", args.resolution);
    }
    if !(args.eps.is_finite() && args.eps >= 0.0) {
        anyhow::bail!("--eps: {} must be a finite number >= 0", args.eps);
    }
    for (flag, n) in [("--repeats", args.repeats), ("--multi-repeats", args.multi_repeats)] {
        if n == 0 || n > 1000 {
            anyhow::bail!("{flag} must be in 1..=1000, got {n}");
        }
    }
    let mut sets = render_sets(&args.set)?;
    sets.push(("resolution".into(), args.resolution.to_string()));
    let scene = Scene::load(&args.scene, &sets)?;
    let plain = maps_list("--plain", &args.plain, false)?;
    let hybrids = maps_list("--hybrid", &args.hybrid, true)?;
    let multi_specs: Vec<String> = args.multi.iter().filter(|s| !s.trim().is_empty()).cloned().collect();
    let multi = methods_list::parse_methods(&multi_specs)?;
    let multi_plain: Vec<u32> = maps_list("--multi-plain", &args.multi_plain, false)?
        .into_iter()
        .map(|(_, m)| match m {
            hybrid::Maps::Plain(size) => size,
            hybrid::Maps::Hybrid { .. } => unreachable!("plain sizes parse as plain maps"),
        })
        .collect();
    let multi_hybrid = parse_maps(&args.multi_hybrid, true).with_context(|| "--multi-hybrid")?;
    // Every (method, maps) pair the flags fix is checked against the light now: a refusal after
    // the hard part's minutes of measuring would throw them away.
    for (flag, list) in [("--plain", &plain), ("--hybrid", &hybrids)] {
        for (text, maps) in list {
            Method::hard().check_light(&maps.apply(&scene, args.eps)).with_context(|| format!("{flag} {text}"))?;
        }
    }
    for (spec, method) in multi_specs.iter().zip(&multi) {
        method.check_light(&multi_hybrid.apply(&scene, args.eps)).with_context(|| format!("--multi {spec} with --multi-hybrid {}", args.multi_hybrid))?;
        // The plain sizes (given and of equal memory) differ only in size, which no light refuses.
        method.check_light(&hybrid::Maps::Plain(scene.render.shadow_map_size).apply(&scene, args.eps)).with_context(|| format!("--multi {spec}"))?;
    }
    let job = hybrid::HybridJob {
        scene,
        hard: plain.iter().chain(&hybrids).map(|(_, m)| *m).collect(),
        eps: args.eps,
        repeats: args.repeats,
        multi,
        multi_hybrid,
        multi_plain,
        multi_repeats: args.multi_repeats,
        cache: truth::Cache::default_for(false),
    };
    let ctx = GpuContext::with_request(gpu)?;
    let outcome = hybrid::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    run_files::write_files(&args.out, &outcome.files)?;
    print!("{}", hybrid::files::markdown(&outcome.rows));
    println!("adapter: {} ({}); wall clock", ctx.summary.name, ctx.summary.backend);
    println!("study: {}", args.out.join("hybrid.md").display());
    Ok(())
}

/// A comma list of map configurations (blank entries skipped), each with its text, given once each.
fn maps_list(flag: &str, values: &[String], hybrid: bool) -> Result<Vec<(String, hybrid::Maps)>> {
    let maps = values.iter().filter(|s| !s.trim().is_empty()).map(|v| Ok((v.trim().to_string(), parse_maps(v, hybrid).with_context(|| flag.to_string())?))).collect::<Result<Vec<_>>>()?;
    listed_once(flag, maps.iter().map(|(t, m)| (t, *m)))?;
    Ok(maps)
}
