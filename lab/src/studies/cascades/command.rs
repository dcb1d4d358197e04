//! `penumbra cascades`: the sun's cascaded shadow maps for each number of cascades and split
//! scheme, their error against the continuous reference and each cascade's texel density on
//! screen (docs/lights.md "Cascades").

use super::render_sets;
use anyhow::{bail, Result};
use penumbra_lab::gpu::{AdapterRequest, GpuContext};
use penumbra_lab::methods::cascades::{split::Scheme, CascadeMaps, FILTERS, MAX_CASCADES};
use penumbra_lab::methods::Method;
use penumbra_lab::record::{output_set, run_files};
use penumbra_lab::reference::truth;
use penumbra_lab::scene::Scene;
use penumbra_lab::studies::cascades::{self, files, CascadeJob};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct CascadesArgs {
    /// Built-in scene name or path to a scene TOML file; its light must be a `sun`.
    #[arg(long, default_value = "sun-grove", value_parser = crate::cli::utf8())]
    scene: String,
    /// Numbers of cascades, each in 1..=8, e.g. `--n 1,2,4`.
    #[arg(long, value_delimiter = ',', default_value = "1,2,3,4")]
    n: Vec<String>,
    /// Split schemes: uniform, log, practical.
    #[arg(long, value_delimiter = ',', default_value = "uniform,log,practical")]
    split: Vec<String>,
    /// The practical scheme's weight of the log split, in 0..=1.
    #[arg(long, default_value = "0.5", allow_hyphen_values = true)]
    lambda: String,
    /// Each map read with one test (`hard`) or pcf's taps (`pcf`).
    #[arg(long, default_value = "hard")]
    filter: String,
    /// Ground truth: `continuous` or `lattice`.
    #[arg(long, default_value = "continuous")]
    reference: String,
    /// M for the continuous reference (M×M samples).
    #[arg(long, default_value_t = 32)]
    samples: u32,
    /// Override a render setting, e.g. `--set resolution=128 --set shadow_map_size=256`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    #[arg(long, default_value = "penumbra-out/cascades")]
    out: PathBuf,
    /// Trace the reference even when the cache holds it.
    #[arg(long)]
    no_cache: bool,
}

/// `--n 1,2,4`: each in 1..=MAX_CASCADES, no repeats.
fn parse_n(values: &[String]) -> Result<Vec<u32>> {
    let mut out = Vec::new();
    for v in values {
        let n: u32 = match v.trim().parse() {
            Ok(n) if (1..=MAX_CASCADES).contains(&n) => n,
            _ => bail!("--n {v}: each number of cascades must be a whole number in 1..={MAX_CASCADES}"),
        };
        if out.contains(&n) {
            bail!("--n {v}: given twice");
        }
        out.push(n);
    }
    Ok(out)
}

fn parse_split(values: &[String]) -> Result<Vec<Scheme>> {
    let mut out = Vec::new();
    for v in values {
        let Some(s) = Scheme::parse(v.trim()) else {
            bail!("--split {v}: use uniform, log or practical");
        };
        if out.contains(&s) {
            bail!("--split {v}: given twice");
        }
        out.push(s);
    }
    Ok(out)
}

pub fn run(args: CascadesArgs, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&args.out)?;
    let ns = parse_n(&args.n)?;
    let schemes = parse_split(&args.split)?;
    let lambda = match args.lambda.trim().parse::<f32>() {
        Ok(l) if (0.0..=1.0).contains(&l) => l,
        _ => bail!("--lambda {}: the log split's weight must be a number in 0..=1", args.lambda),
    };
    let Some(&filter) = FILTERS.iter().find(|f| **f == args.filter) else {
        bail!("--filter {}: use {}", args.filter, FILTERS.join(" or "));
    };
    let mode = truth::parse_mode(&args.reference, args.samples)?;
    let sets = render_sets(&args.set)?;
    let scene = Scene::load(&args.scene, &sets)?;
    let methods: Vec<Method> = schemes
        .iter()
        .flat_map(|&split| ns.iter().map(move |&n| Method::new(CascadeMaps { n, split, lambda, filter })))
        .collect();
    // The light's kind and every frame's sizes before the reference is traced or anything written.
    penumbra_lab::methods::check_lights(&scene, &methods)?;
    let ctx = GpuContext::with_request(gpu)?;
    penumbra_lab::methods::sizes::check_all(&ctx, &scene, &methods)?;
    eprintln!("cascades: {} settings on {} ({} triangles)", methods.len(), scene.name, scene.triangle_count());
    let job = CascadeJob { scene: &scene, ns, schemes, lambda, filter, reference: mode, cache: truth::Cache::default_for(args.no_cache) };
    let lines = cascades::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    run_files::write_files(&args.out, &files::files(&lines)?)?;
    let md = files::markdown(&lines);
    print!("{}", md.split("\n## Each cascade").next().unwrap_or(&md));
    println!("\ncascades: {}", args.out.join("cascades.jsonl").display());
    println!("report:   {}", args.out.join("report.html").display());
    Ok(())
}
