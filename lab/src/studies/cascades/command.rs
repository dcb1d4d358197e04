//! `penumbra cascades`: the sun's cascaded shadow maps for each number of cascades and split
//! scheme, their error against the continuous reference and each cascade's texel density on
//! screen (docs/lights.md "Cascades").

use crate::gpu::{AdapterRequest, GpuContext};
use crate::methods::cascades::{split::Scheme, CascadeMaps, FILTERS, MAX_CASCADES};
use crate::methods::Method;
use crate::record::run_files;
use crate::reference::truth;
use crate::scene::Scene;
use crate::studies::cascades::{self, files, CascadeJob};
use crate::studies::flags::{OutArgs, SceneArgs, SetArgs};
use anyhow::{bail, Result};

#[derive(clap::Args)]
#[command(mut_arg("scene", |a| a.default_value("sun-grove").help("Built-in scene name or path to a scene TOML file; its light must be a `sun`")))]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/cascades")))]
pub struct CascadesArgs {
    #[command(flatten)]
    scene: SceneArgs,
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
    #[command(flatten)]
    sets: SetArgs,
    #[command(flatten)]
    output: OutArgs,
    /// Trace the reference without the cache: nothing is read from it or stored in it.
    #[arg(long)]
    no_cache: bool,
}

/// `--n 1,2,4`: each in 1..=MAX_CASCADES, no repeats.
fn parse_n(values: &[String]) -> Result<Vec<u32>> {
    let mut out = Vec::new();
    for v in values {
        let n: u32 = match v.trim().parse() {
            Ok(n) if (1..=MAX_CASCADES).contains(&n) => n,
            _ => bail!(
                "--n {v}: each number of cascades must be a whole number in 1..={MAX_CASCADES}"
            ),
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

impl crate::studies::Run for CascadesArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: CascadesArgs, gpu: &AdapterRequest) -> Result<()> {
    let out = args.output.checked()?;
    let ns = parse_n(&args.n)?;
    let schemes = parse_split(&args.split)?;
    let lambda = match args.lambda.trim().parse::<f32>() {
        Ok(l) if (0.0..=1.0).contains(&l) => l,
        _ => bail!(
            "--lambda {}: the log split's weight must be a number in 0..=1",
            args.lambda
        ),
    };
    let Some(&filter) = FILTERS.iter().find(|f| **f == args.filter) else {
        bail!("--filter {}: use {}", args.filter, FILTERS.join(" or "));
    };
    let mode = truth::parse_mode(&args.reference, args.samples)?;
    let sets = args.sets.render()?;
    let scene = Scene::load(&args.scene.scene, &sets)?;
    let methods: Vec<Method> = schemes
        .iter()
        .flat_map(|&split| {
            ns.iter().map(move |&n| {
                Method::new(CascadeMaps {
                    n,
                    split,
                    lambda,
                    filter,
                })
            })
        })
        .collect();
    // The light's kind and every frame's sizes before the reference is traced or anything written.
    crate::methods::check_lights(&scene, &methods)?;
    let ctx = GpuContext::with_request(gpu)?;
    crate::methods::sizes::check_all(&ctx, &scene, &methods)?;
    eprintln!(
        "cascades: {} settings on {} ({} triangles)",
        methods.len(),
        scene.name,
        scene.triangle_count()
    );
    let job = CascadeJob {
        scene: &scene,
        ns,
        schemes,
        lambda,
        filter,
        reference: mode,
        cache: truth::Cache::default_for(args.no_cache),
    };
    let lines = cascades::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    run_files::write_files(out, &files::files(&lines)?)?;
    let md = files::markdown(&lines);
    print!("{}", md.split("\n## Each cascade").next().unwrap_or(&md));
    println!("\ncascades: {}", out.join("cascades.jsonl").display());
    println!("report:   {}", out.join("report.html").display());
    Ok(())
}
