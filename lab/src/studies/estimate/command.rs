//! `penumbra estimate`: the error estimate checked against the truth on scenes × grid settings
//! (docs/error-estimate.md §5).

use super::render_sets;
use anyhow::Result;
use penumbra_lab::gpu::{AdapterRequest, GpuContext};
use penumbra_lab::record::{output_set, run_files};
use penumbra_lab::reference::truth;
use penumbra_lab::scene::Scene;
use penumbra_lab::studies::estimate::{self, Setting};
use penumbra_lab::studies::lists::listed_once;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct EstimateArgs {
    /// Scenes (built-in names or TOML paths), comma-separated; default: every built-in scene lit by an area light.
    #[arg(long, value_delimiter = ',', value_parser = crate::cli::utf8())]
    scenes: Vec<String>,
    /// Settings as SPEC@MAP_SIZE, comma-separated between settings with `;`, e.g.
    /// `regular:n=5,layout=centred@1024;regular:n=17@512`; default: the six of docs/error-estimate.md.
    #[arg(long)]
    settings: Option<String>,
    /// M for the continuous reference (M×M samples).
    #[arg(long, default_value_t = 32)]
    samples: u32,
    /// Override a render setting, e.g. `--set resolution=128` (map sizes come from the settings).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    #[arg(long, default_value = "penumbra-out/estimate")]
    out: PathBuf,
    /// Trace the reference even when the cache holds it.
    #[arg(long)]
    no_cache: bool,
}

pub fn run(args: EstimateArgs, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&args.out)?;
    let mode = truth::parse_mode("continuous", args.samples)?;
    let sets = render_sets(&args.set)?;
    if let Some((k, v)) = sets.iter().find(|(k, _)| k.strip_prefix("render.").unwrap_or(k) == "shadow_map_size") {
        anyhow::bail!("--set {k}={v}: each setting names its map size (SPEC@SIZE in --settings)");
    }
    let settings: Vec<Setting> = match &args.settings {
        Some(text) => {
            let settings = text.split(';').map(|s| Setting::parse(s.trim())).collect::<penumbra_lab::Result<Vec<_>>>()?;
            // One setting however it is spelled: the method's label and the map size.
            listed_once("--settings", text.split(';').zip(settings.iter().map(Setting::key)))?;
            settings
        }
        None => estimate::DEFAULT_SETTINGS.iter().map(|(spec, size)| Setting { spec: spec.to_string(), map_size: *size }).collect(),
    };
    let scenes: Vec<String> = if args.scenes.is_empty() {
        penumbra_lab::scene::area_light_names().iter().map(|s| s.to_string()).collect()
    } else {
        listed_once("--scenes", args.scenes.iter().map(|s| (s, s.trim())))?;
        args.scenes.clone()
    };
    // Every scene loads and is lit by an area light before anything is traced.
    for name in &scenes {
        if Scene::load(name, &sets)?.environment.is_some() {
            anyhow::bail!("--scenes {name}: lit by a panorama; the estimate is built for the area lights' grids");
        }
    }
    let ctx = GpuContext::with_request(gpu)?;
    let cache = truth::Cache::default_for(args.no_cache);
    let mut lines = Vec::new();
    for name in &scenes {
        lines.extend(estimate::run_scene(&ctx, name, &sets, &settings, mode, &cache, &|l| eprintln!("{l}"))?);
    }
    run_files::write_files(&args.out, &estimate::files(&lines)?)?;
    if let Some(line) = penumbra_lab::record::failed_summary(lines.iter().filter(|l| l.failed.is_some()).count(), lines.len()) {
        eprintln!("{line}");
    }
    let md = estimate::markdown(&lines);
    print!("{}", md.split("\n| scene").next().unwrap_or(&md));
    println!("\nestimate: {}", args.out.join("estimate.jsonl").display());
    println!("report:   {}", args.out.join("report.html").display());
    Ok(())
}
