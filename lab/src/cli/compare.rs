//! `penumbra compare` (and the main job, `penumbra` with no command): every method on one scene,
//! timed and judged against the reference; results, pictures, charts and the report.

use super::run_args::RunArgs;
use super::{render_sets, DEFAULT_METHODS};
use anyhow::Result;
use penumbra_lab::gpu::{AdapterRequest, GpuContext};
use penumbra_lab::methods::Method;
use penumbra_lab::record::{output_set, Provenance};
use penumbra_lab::reference::truth;
use penumbra_lab::scene::Scene;
use penumbra_lab::studies::compare::{self, methods_list, plan, CompareJob};
use penumbra_lab::studies::failures::{self, GalleryJob};
use std::path::PathBuf;


#[derive(clap::Args)]
pub struct CompareArgs {
    /// Methods, comma-separated: `hard,regular:n=5,adaptive:p_m=0,scope=local` (repeatable).
    #[arg(long, default_value = DEFAULT_METHODS)]
    methods: Vec<String>,
    /// Refuse more methods than N (a guard against a list that would run for hours).
    #[arg(long, value_name = "N", default_value_t = plan::DEFAULT_MAX_CONFIGS)]
    max_configs: usize,
    #[command(flatten)]
    run: RunArgs,
}

pub fn run(args: CompareArgs, gpu: &AdapterRequest) -> Result<()> {
    compare_methods(&args.methods, args.max_configs, args.run, None, gpu)
}

/// `penumbra` with no command: the default methods on `default`, with the failure gallery.
pub fn main_job(out: PathBuf, gpu: &AdapterRequest) -> Result<()> {
    let run = RunArgs { scene: "default".into(), repeats: 3, reference: "continuous".into(), samples: 32, set: Vec::new(), out, no_cache: false };
    let gallery = super::failures::FailuresArgs::main_job(&run);
    compare_methods(&[DEFAULT_METHODS.to_string()], plan::DEFAULT_MAX_CONFIGS, run, Some(gallery), gpu)
}

fn compare_methods(values: &[String], max_configs: usize, run: RunArgs, gallery: Option<super::failures::FailuresArgs>, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&run.out)?;
    let gallery_job = gallery.as_ref().map(|g| g.job()).transpose()?;
    let specs = methods_list::split_specs(values)?;
    plan::check_count(specs.len(), max_configs, "--methods")?;
    let methods = methods_list::parse_methods(&specs)?;
    let scene = Scene::load(&run.scene, &render_sets(&run.set)?)?;
    let provenance = Provenance::of_scene("compare", &scene, &run.set, None);
    let all = vec![provenance; methods.len()];
    // A short list needs no forecast: its per-method lines follow within a minute or so.
    let announce = methods.len() > plan::COMPARE_ANNOUNCE_OVER;
    run_compare(methods, scene, all, run, gallery_job, gpu, announce)
}

/// Everything the user gave is checked before the GPU starts or any file is written. With
/// `gallery_job`, the failure gallery runs too and its sections join the report. With `announce`,
/// the count and the time estimate are printed first (`plan::line`).
pub fn run_compare(
    methods: Vec<Method>,
    scene: Scene,
    provenance: Vec<Provenance>,
    run: RunArgs,
    gallery_job: Option<GalleryJob>,
    gpu: &AdapterRequest,
    announce: bool,
) -> Result<()> {
    let mode = truth::parse_mode(&run.reference, run.samples)?;
    if run.repeats == 0 || run.repeats > 1000 {
        anyhow::bail!("--repeats must be in 1..=1000, got {}", run.repeats);
    }
    penumbra_lab::methods::check_lights(&scene, &methods)?;
    if announce {
        eprintln!("{}", plan::line(&methods, &scene, run.repeats));
    }
    let ctx = GpuContext::with_request(gpu)?;
    // Every method's frame sizes before the reference is traced or anything is written.
    penumbra_lab::methods::sizes::check_all(&ctx, &scene, &methods)?;
    let cache = truth::Cache::default_for(run.no_cache);
    let pictures = penumbra_lab::studies::regions::wants_pictures(&methods);
    let job = CompareJob { scene: &scene, methods, repeats: run.repeats, reference: mode, cache, provenance, pictures };
    let outcome = compare::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    let gallery = gallery_job.map(|g| failures::run(&ctx, &g, &|line| eprintln!("{line}"))).transpose()?;
    let html = compare::write(&run.out, &outcome)?;
    if pictures {
        penumbra_lab::studies::regions::append(&html, &job.methods, &outcome.pictures)?;
    }
    if let Some(g) = &gallery {
        failures::attach(&run.out, g)?;
    }
    print!("{}", compare::table::render(&outcome.rows));
    println!("adapter: {} ({}); reference: {}", ctx.summary.name, ctx.summary.backend, truth::mode_label(&mode));
    println!("results: {}", run.out.join("results.jsonl").display());
    println!("report:  {}", html.display());
    Ok(())
}
