//! `penumbra reference`: the CPU ground truth of one scene (cached), as EXR, PNG and a record.

use anyhow::{Context, Result};
use penumbra_lab::gpu::{AdapterRequest, GpuContext};
use penumbra_lab::record::run_files;
use penumbra_lab::reference::truth;
use penumbra_lab::scene::Scene;
use penumbra_lab::studies::compare;
use penumbra_lab::studies::flags::{OutArgs, SceneArgs, SetArgs};
use penumbra_lab::studies::Run;

#[derive(clap::Args)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/reference")))]
pub struct ReferenceArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// `continuous` (M×M stratified jitter, fixed seed), `lattice` (the 289 lattice points) or
    /// `point` (exact hard-shadow visibility from one light point: the centre, or `--point`).
    #[arg(long, default_value = "continuous")]
    mode: String,
    /// M for the continuous mode.
    #[arg(long, default_value_t = 32)]
    samples: u32,
    /// With `--mode point`: the light point as light coordinates `S,T` in [0, 1] (default 0.5,0.5).
    #[arg(long, value_name = "S,T")]
    point: Option<String>,
    #[command(flatten)]
    sets: SetArgs,
    #[command(flatten)]
    output: OutArgs,
    /// Trace without the cache: nothing is read from it or stored in it.
    #[arg(long)]
    no_cache: bool,
    /// Who traces: `cpu` (the lab's tracer), `gpu` (`truth_trace`, the same values), or `auto`
    /// (the GPU where the adapter is a real GPU, else the CPU).
    #[arg(long, default_value = "auto")]
    tracer: String,
}

impl Run for ReferenceArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: ReferenceArgs, gpu: &AdapterRequest) -> Result<()> {
    let out = args.output.checked()?;
    let scene = Scene::load(&args.scene.scene, &args.sets.render()?)?;
    let mode = match (&args.point, args.mode.as_str()) {
        (None, m) => truth::parse_mode(m, args.samples)?,
        (Some(p), "point") => {
            truth::parse_mode(&format!("point:{p}"), args.samples).context("--point")?
        }
        (Some(_), m) => anyhow::bail!("--point is for --mode point, not --mode {m}"),
    };
    let tracer = truth::TracerChoice::parse(&args.tracer)?;
    let ctx = GpuContext::with_request(gpu)?;
    let (g, image) = truth::for_scene_with(
        &ctx,
        &scene,
        mode,
        &truth::Cache::default_for(args.no_cache),
        tracer,
    )?;
    let (w, h) = (image.width, image.height);
    let geometry = g.geometry_count();
    let record = serde_json::to_vec_pretty(&image.record(&scene, geometry))?;
    let files = vec![
        (
            "reference.exr".to_string(),
            run_files::visibility_exr(&image.values, w, h)?,
        ),
        (
            "reference.png".to_string(),
            run_files::visibility_png(&image.values, w, h)?,
        ),
        (
            "reference_shaded.png".to_string(),
            run_files::png(&run_files::shaded_image(&image.values, &g, &scene))?,
        ),
        ("reference.json".to_string(), record),
    ];
    run_files::write_files(out, &files)?;
    println!("{}", compare::reference_line(&image, geometry));
    for (name, _) in &files {
        println!("  {}", out.join(name).display());
    }
    Ok(())
}
