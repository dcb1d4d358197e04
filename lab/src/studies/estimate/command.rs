//! `penumbra estimate`: the error estimate checked against the truth on scenes × grid settings
//! (docs/error-estimate.md §5).

use crate::gpu::{AdapterRequest, GpuContext};
use crate::record::run_files;
use crate::reference::truth;
use crate::scene::Scene;
use crate::studies::estimate::{self, Setting};
use crate::studies::flags::{OutArgs, SetArgs};
use crate::studies::lists::listed_once;
use anyhow::Result;

#[derive(clap::Args)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/estimate")))]
pub struct EstimateArgs {
    /// Scenes (built-in names or TOML paths), comma-separated; default: every built-in scene lit by an area light.
    #[arg(long, value_delimiter = ',', value_parser = crate::studies::flags::utf8())]
    scenes: Vec<String>,
    /// Settings as SPEC@MAP_SIZE, comma-separated between settings with `;`, e.g.
    /// `regular:n=5,layout=centred@1024;regular:n=17@512`; default: the six of docs/error-estimate.md.
    #[arg(long)]
    settings: Option<String>,
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

impl crate::studies::Run for EstimateArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: EstimateArgs, gpu: &AdapterRequest) -> Result<()> {
    args.output.checked()?;
    let mode = truth::parse_mode("continuous", args.samples)?;
    let sets = args.sets.render()?;
    if let Some((k, v)) = sets
        .iter()
        .find(|(k, _)| k.strip_prefix("render.").unwrap_or(k) == "shadow_map_size")
    {
        anyhow::bail!("--set {k}={v}: each setting names its map size (SPEC@SIZE in --settings)");
    }
    let settings: Vec<Setting> = match &args.settings {
        Some(text) => {
            let settings = text
                .split(';')
                .map(|s| Setting::parse(s.trim()))
                .collect::<crate::Result<Vec<_>>>()?;
            // One setting however it is spelled: the method's label and the map size.
            listed_once(
                "--settings",
                text.split(';').zip(settings.iter().map(Setting::key)),
            )?;
            settings
        }
        None => estimate::DEFAULT_SETTINGS
            .iter()
            .map(|(spec, size)| Setting {
                spec: spec.to_string(),
                map_size: *size,
            })
            .collect(),
    };
    let scenes: Vec<String> = if args.scenes.is_empty() {
        crate::scene::area_light_names()
            .iter()
            .map(|s| s.to_string())
            .collect()
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
        lines.extend(estimate::run_scene(
            &ctx,
            name,
            &sets,
            &settings,
            mode,
            &cache,
            &|l| eprintln!("{l}"),
        )?);
    }
    run_files::write_files(&args.output.out, &estimate::files(&lines)?)?;
    if let Some(line) = crate::record::failed_summary(
        lines.iter().filter(|l| l.failed.is_some()).count(),
        lines.len(),
    ) {
        eprintln!("{line}");
    }
    let md = estimate::markdown(&lines);
    print!("{}", md.split("\n| scene").next().unwrap_or(&md));
    println!(
        "\nestimate: {}",
        args.output.out.join("estimate.jsonl").display()
    );
    println!(
        "report:   {}",
        args.output.out.join("report.html").display()
    );
    Ok(())
}
