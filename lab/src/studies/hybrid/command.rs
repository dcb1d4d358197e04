//! `penumbra hybrid`: hybrid-resolution shadow maps (seed 003) against plain maps.

use crate::gpu::{AdapterRequest, GpuContext};
use crate::methods::Method;
use crate::record::run_files;
use crate::reference::truth;
use crate::scene::Scene;
use crate::studies::compare::methods_list;
use crate::studies::flags::{repeats_in_range, OutArgs, RepeatsArgs, SceneArgs, SetArgs};
use crate::studies::hybrid::{self, parse_maps};
use crate::studies::lists::listed_once;
use anyhow::{Context, Result};

#[derive(clap::Args)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/hybrid")))]
pub struct HybridArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Square screen size in pixels.
    #[arg(long, default_value_t = 256)]
    resolution: u32,
    /// Plain map sizes of the hard-shadow part, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "512,1024,2048,4096")]
    plain: Vec<String>,
    /// Hybrid maps of the hard-shadow part as BASE/LEVELS, comma-separated (2048/2 is 2048 → 512).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1024/1,2048/1,2048/2,4096/2"
    )]
    hybrid: Vec<String>,
    /// Merge tolerance in 16-bit depth units (the seed's 0.25).
    #[arg(long, default_value_t = 0.25)]
    eps: f32,
    #[command(flatten)]
    repeats: RepeatsArgs,
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
    #[command(flatten)]
    sets: SetArgs,
    #[command(flatten)]
    output: OutArgs,
}

impl crate::studies::Run for HybridArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: HybridArgs, gpu: &AdapterRequest) -> Result<()> {
    args.output.checked()?;
    if !(8..=4096).contains(&args.resolution) {
        anyhow::bail!("--resolution: {} is not in 8..=4096", args.resolution);
    }
    if !(args.eps.is_finite() && args.eps >= 0.0) {
        anyhow::bail!("--eps: {} must be a finite number >= 0", args.eps);
    }
    let repeats = args.repeats.checked()?;
    let multi_repeats = repeats_in_range("--multi-repeats", args.multi_repeats)?;
    let mut sets = args.sets.render()?;
    sets.push(("resolution".into(), args.resolution.to_string()));
    let scene = Scene::load(&args.scene.scene, &sets)?;
    let plain = maps_list("--plain", &args.plain, false)?;
    let hybrids = maps_list("--hybrid", &args.hybrid, true)?;
    let multi_specs: Vec<String> = args
        .multi
        .iter()
        .filter(|s| !s.trim().is_empty())
        .cloned()
        .collect();
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
            Method::hard()
                .check_light(&maps.apply(&scene, args.eps))
                .with_context(|| format!("{flag} {text}"))?;
        }
    }
    for (spec, method) in multi_specs.iter().zip(&multi) {
        method
            .check_light(&multi_hybrid.apply(&scene, args.eps))
            .with_context(|| format!("--multi {spec} with --multi-hybrid {}", args.multi_hybrid))?;
        // The plain sizes (given and of equal memory) differ only in size, which no light refuses.
        method
            .check_light(&hybrid::Maps::Plain(scene.render.shadow_map_size).apply(&scene, args.eps))
            .with_context(|| format!("--multi {spec}"))?;
    }
    let job = hybrid::HybridJob {
        scene,
        hard: plain.iter().chain(&hybrids).map(|(_, m)| *m).collect(),
        eps: args.eps,
        repeats,
        multi,
        multi_hybrid,
        multi_plain,
        multi_repeats,
        cache: truth::Cache::default_for(false),
    };
    let ctx = GpuContext::with_request(gpu)?;
    let outcome = hybrid::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    run_files::write_files(&args.output.out, &outcome.files)?;
    print!("{}", hybrid::files::markdown(&outcome.rows));
    println!(
        "adapter: {} ({}); wall clock",
        ctx.summary.name, ctx.summary.backend
    );
    println!("study: {}", args.output.out.join("hybrid.md").display());
    Ok(())
}

/// A comma list of map configurations (blank entries skipped), each with its text, given once each.
fn maps_list(flag: &str, values: &[String], hybrid: bool) -> Result<Vec<(String, hybrid::Maps)>> {
    let maps = values
        .iter()
        .filter(|s| !s.trim().is_empty())
        .map(|v| {
            Ok((
                v.trim().to_string(),
                parse_maps(v, hybrid).with_context(|| flag.to_string())?,
            ))
        })
        .collect::<Result<Vec<_>>>()?;
    listed_once(flag, maps.iter().map(|(t, m)| (t, *m)))?;
    Ok(maps)
}
