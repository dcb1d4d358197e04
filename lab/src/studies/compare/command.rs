//! `penumbra compare` (and the main job, `penumbra` with no command): every method on one scene,
//! timed and judged against the reference; results, pictures, charts and the report.

use super::run_args::RunArgs;
use super::DEFAULT_METHODS;
use crate::gpu::{AdapterRequest, GpuContext};
use crate::methods::Method;
use crate::record::Provenance;
use crate::reference::truth;
use crate::scene::Scene;
use crate::studies::compare::{self, methods_list, plan, CompareJob};
use crate::studies::failures::{self, command::FailuresArgs, GalleryJob};
use crate::studies::flags::{OutArgs, RepeatsArgs, SceneArgs, SetArgs};
use anyhow::Result;
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

impl crate::studies::Run for CompareArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        compare_methods(&self.methods, self.max_configs, self.run, None, gpu)
    }
}

/// `penumbra` with no command: the default methods on `default`, with the failure gallery.
pub fn main_job(out: PathBuf, gpu: &AdapterRequest) -> Result<()> {
    let run = RunArgs {
        scene: SceneArgs {
            scene: "default".into(),
        },
        repeats: RepeatsArgs { repeats: 3 },
        reference: "continuous".into(),
        samples: 32,
        sets: SetArgs::default(),
        output: OutArgs { out },
        no_cache: false,
        certify: None,
        delta: None,
    };
    let gallery = FailuresArgs::main_job(&run);
    compare_methods(
        &[super::MAIN_JOB_METHODS.to_string()],
        plan::DEFAULT_MAX_CONFIGS,
        run,
        Some(gallery),
        gpu,
    )
}

fn compare_methods(
    values: &[String],
    max_configs: usize,
    run: RunArgs,
    gallery: Option<FailuresArgs>,
    gpu: &AdapterRequest,
) -> Result<()> {
    run.output.checked()?;
    let gallery_job = gallery.as_ref().map(|g| g.job()).transpose()?;
    let specs = methods_list::split_specs(values)?;
    plan::check_count(specs.len(), max_configs, "--methods")?;
    let methods = methods_list::parse_methods(&specs)?;
    let scene = Scene::load(&run.scene.scene, &run.sets.render()?)?;
    let provenance = Provenance::of_scene("compare", &scene, &run.sets.set, None);
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
    let repeats = run.repeats.checked()?;
    let certify = crate::studies::flags::certify_options(run.certify, run.delta, &scene)?;
    crate::methods::check_lights(&scene, &methods)?;
    if announce {
        eprintln!("{}", plan::line(&methods, &scene, repeats));
    }
    let ctx = GpuContext::with_request(gpu)?;
    // Every method's frame sizes before the reference is traced or anything is written.
    crate::methods::sizes::check_all(&ctx, &scene, &methods)?;
    let cache = truth::Cache::default_for(run.no_cache);
    let pictures = super::regions::wants_pictures(&methods);
    let job = CompareJob {
        scene: &scene,
        methods,
        repeats,
        reference: mode,
        cache,
        provenance,
        pictures,
        certify,
    };
    let outcome = compare::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    let gallery = gallery_job
        .map(|g| failures::run(&ctx, &g, &|line| eprintln!("{line}")))
        .transpose()?;
    let out = &run.output.out;
    let html = compare::write(out, &outcome)?;
    if pictures {
        super::regions::append(&html, &job.methods, &outcome.pictures)?;
    }
    if let Some(g) = &gallery {
        failures::attach(out, g)?;
    }
    print!("{}", compare::table::render(&outcome.rows));
    for r in outcome.rows.iter().filter(|r| r.measured()) {
        if let Some(c) = &r.certify {
            println!(
                "certified: {}: {} (measured {:.4})",
                r.label(),
                c.line(),
                r.metrics.rmse
            );
        }
    }
    println!(
        "adapter: {} ({}); reference: {}",
        ctx.summary.name,
        ctx.summary.backend,
        truth::mode_label(&mode)
    );
    println!("results: {}", out.join("results.jsonl").display());
    println!("report:  {}", html.display());
    Ok(())
}
