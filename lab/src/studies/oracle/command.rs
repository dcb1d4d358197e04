//! `penumbra oracle`: the most any per-region method could gain on a scene (docs/oracle.md).

use super::{family, OracleJob};
use crate::gpu::{AdapterRequest, GpuContext};
use crate::record::run_files;
use crate::reference::truth;
use crate::scene::Scene;
use crate::studies::compare::plan;
use crate::studies::flags::{OutArgs, RepeatsArgs, SetArgs};
use crate::studies::frontier::grid;
use crate::studies::lists::listed_once;
use anyhow::Result;

/// The most any per-region method could gain: every candidate (culled centred grids, one-map
/// filters, hybrid maps, adaptive presets) rendered once, each 8×8 tile given the one that meets
/// the target at the least price, against the cheapest single setting meeting it (oracle.csv,
/// candidates.csv, tiles/*.png, charts/gain_bound.svg, report.html; docs/oracle.md).
#[derive(clap::Args)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/oracle")))]
pub struct OracleArgs {
    /// Scenes (built-in names or TOML files), repeatable or comma-separated.
    #[arg(long = "scene", value_delimiter = ',', required = true, value_parser = crate::studies::flags::utf8())]
    scenes: Vec<String>,
    /// Square screen sizes in pixels, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "128")]
    resolutions: Vec<String>,
    /// Targets T (RMSE of V), comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "0.03,0.02,0.012")]
    targets: Vec<String>,
    /// Samples per side of the culled centred grids.
    #[arg(long, value_delimiter = ',', default_value = "1,2,3,4,6,8,11,16")]
    n: Vec<String>,
    /// Plain map sides of every candidate.
    #[arg(long, value_delimiter = ',', default_value = "512,1024,2048")]
    sizes: Vec<String>,
    /// Methods of one map at each side (and on hybrid maps where they read them), or `none`.
    #[arg(long, value_delimiter = ',', default_value = "pcss,pcf,msm")]
    singles: Vec<String>,
    /// Hybrid maps as BASE/LEVELS (centred grids and filters on them), or `none`.
    #[arg(long, value_delimiter = ',', default_value = family::HYBRID)]
    hybrid: Vec<String>,
    /// Adaptive presets at each side: seed, balanced, seed-local, balanced-local; or `none`.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "seed,balanced,seed-local,balanced-local"
    )]
    adaptive: Vec<String>,
    #[command(flatten)]
    repeats: RepeatsArgs,
    /// M for the continuous reference (M×M samples).
    #[arg(long, default_value_t = 32)]
    samples: u32,
    #[command(flatten)]
    sets: SetArgs,
    /// Refuse more candidates (over all scenes and screens) than N.
    #[arg(long, value_name = "N", default_value_t = plan::DEFAULT_MAX_CONFIGS)]
    max_configs: usize,
    #[command(flatten)]
    output: OutArgs,
    /// Trace the reference even when the cache holds it.
    #[arg(long)]
    no_cache: bool,
}

/// Render settings the menu and `--resolutions` set themselves.
const OWN_KEYS: [&str; 11] = [
    "shadow_map_size",
    "maps",
    "base",
    "levels",
    "eps",
    "hybrid.base",
    "hybrid.levels",
    "hybrid.eps",
    "resolution",
    "width",
    "height",
];

impl crate::studies::Run for OracleArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

/// `--targets 0.03,0.02`: each an RMSE of V in 0.0005..=0.5, listed once.
fn parse_targets(list: &[String]) -> Result<Vec<f64>> {
    let targets = list
        .iter()
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| (0.0005..=0.5).contains(v))
                .ok_or_else(|| {
                    anyhow::anyhow!("--targets `{t}`: a target RMSE of V in 0.0005..=0.5")
                })
        })
        .collect::<Result<Vec<f64>>>()?;
    listed_once(
        "--targets",
        list.iter().zip(targets.iter().map(|t| t.to_bits())),
    )?;
    Ok(targets)
}

/// `--resolutions 128,256`: each in 8..=4096, listed once.
fn parse_resolutions(list: &[String]) -> Result<Vec<u32>> {
    let r = list
        .iter()
        .map(|v| {
            v.trim()
                .parse::<u32>()
                .ok()
                .filter(|r| (8..=4096).contains(r))
                .ok_or_else(|| {
                    anyhow::anyhow!("--resolutions `{v}`: a screen side in 8..=4096 pixels")
                })
        })
        .collect::<Result<Vec<u32>>>()?;
    listed_once("--resolutions", list.iter().zip(r.iter().copied()))?;
    Ok(r)
}

fn run(args: OracleArgs, gpu: &AdapterRequest) -> Result<()> {
    args.output.checked()?;
    let repeats = args.repeats.checked()?;
    let mode = truth::parse_mode("continuous", args.samples)?;
    let sets = args.sets.render()?;
    if let Some((k, v)) = sets
        .iter()
        .find(|(k, _)| OWN_KEYS.contains(&k.strip_prefix("render.").unwrap_or(k)))
    {
        anyhow::bail!("--set {k}={v}: the oracle sets map sizes, map kinds and the screen itself; choose them with --sizes, --hybrid and --resolutions");
    }
    let targets = parse_targets(&args.targets)?;
    let resolutions = parse_resolutions(&args.resolutions)?;
    let menu = family::Menu {
        n: grid::parse_n(&args.n)?,
        sizes: grid::parse_sizes(&args.sizes)?,
        singles: family::parse_singles(&args.singles)?,
        hybrid: grid::parse_hybrid(&args.hybrid)?,
        adaptive: family::parse_adaptive(&args.adaptive)?,
    };
    listed_once("--scene", args.scenes.iter().map(|s| (s, s.trim())))?;
    let mut scenes = Vec::new();
    for name in &args.scenes {
        for &r in &resolutions {
            let mut with = sets.clone();
            with.push(("resolution".into(), r.to_string()));
            let scene = Scene::load(name, &with)?;
            if scene.environment.is_some() {
                anyhow::bail!("--scene {name}: lit by a panorama; the oracle's candidates are the methods of a light's shadow maps");
            }
            scenes.push(scene);
        }
    }
    let budget = scenes
        .first()
        .map_or(512, |s| s.render.shadow_map_budget_mib);
    let (groups, left) = family::groups(&menu, budget)?;
    for line in &left {
        eprintln!("{line}: left out");
    }
    plan::check_count(
        family::count(&groups) * scenes.len(),
        args.max_configs,
        "oracle",
    )?;
    let ctx = GpuContext::with_request(gpu)?;
    let all: Vec<crate::methods::Method> = groups
        .iter()
        .flat_map(|g| g.candidates.iter().map(|c| c.method.clone()))
        .collect();
    for scene in &scenes {
        eprintln!(
            "{} at {}²: {}",
            scene.name,
            scene.render.width,
            plan::line(&all, scene, repeats)
        );
    }
    let job = OracleJob {
        scenes,
        targets,
        menu,
        repeats,
        reference: mode,
        cache: truth::Cache::default_for(args.no_cache),
    };
    let outcome = super::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    run_files::write_files(&args.output.out, &super::files::files(&outcome)?)?;
    let md = super::files::markdown(&outcome);
    print!("{}", md.split("\n## The splits").next().unwrap_or(&md));
    println!("\noracle: {}", args.output.out.join("oracle.csv").display());
    println!("report: {}", args.output.out.join("report.html").display());
    Ok(())
}
