//! `penumbra sequence`: N frames with a moving light, camera or mesh.

use crate::gpu::timing::TimingMode;
use crate::gpu::{AdapterRequest, GpuContext};
use crate::reference::truth;
use crate::scene::Scene;
use crate::studies::compare::methods_list;
use crate::studies::flags::{OutArgs, SceneArgs, SetArgs};
use crate::studies::sequence::path::AnimationSpec;
use crate::studies::sequence::{self, tables, SequenceJob};
use anyhow::Result;

#[derive(clap::Args, Debug, Clone)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/sequence")))]
pub struct SequenceArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Methods, comma-separated as in compare (repeatable).
    #[arg(long, default_value = "hard,regular:n=17,adaptive")]
    methods: Vec<String>,
    /// Frames (2..=1000); each has its own CPU reference.
    #[arg(long, default_value_t = 24)]
    frames: u32,
    /// What moves: light, camera or occluder (one `[[mesh]]`, see --mesh).
    #[arg(long, default_value = "light")]
    animate: String,
    /// segment or circle (light, occluder); orbit or segment (camera). Default: segment, camera orbit.
    #[arg(long)]
    path: Option<String>,
    /// Segment: total displacement `x,y,z` (default: light 2 × edge_u; mesh 0.1 × scene diagonal along x).
    #[arg(long, allow_hyphen_values = true)]
    offset: Option<String>,
    /// Circle radius (default: light |edge_u|; mesh 0.05 × scene diagonal).
    #[arg(long)]
    radius: Option<f32>,
    /// Orbit angle in all, degrees (default 30).
    #[arg(long, allow_hyphen_values = true)]
    degrees: Option<f32>,
    /// The moving mesh for --animate occluder, counted from 1 in file order (default: the last).
    #[arg(long)]
    mesh: Option<u32>,
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
    /// Trace the references without the cache: nothing is read from it or stored in it.
    #[arg(long)]
    no_cache: bool,
    /// Keep each method's shadow maps from frame to frame where nothing they depend on moved:
    /// on, off, or both (each method twice, side by side, V compared bit for bit; docs/reuse.md).
    #[arg(long, default_value = "on")]
    reuse: String,
    /// Clock: frame (each frame's wall time, only the waits the method needs) or stages (a wait
    /// after every stage; each row of frames.jsonl gets `stages_ms`, each stage's wall time).
    #[arg(long, default_value = "frame")]
    timing: String,
}

/// Checks everything the user gave before the GPU starts, runs, writes the set.
impl crate::studies::Run for SequenceArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: SequenceArgs, gpu: &AdapterRequest) -> Result<()> {
    let log = |line: &str| eprintln!("{line}");
    let methods = methods_list::parse_methods(&methods_list::split_specs(&args.methods)?)?;
    let scene = Scene::load(&args.scene.scene, &args.sets.render()?)?;
    let spec = AnimationSpec {
        animate: args.animate.clone(),
        path: args.path.clone(),
        offset: args.offset.clone(),
        radius: args.radius,
        degrees: args.degrees,
        mesh: args.mesh,
    };
    let animation = spec.resolve(&scene)?;
    let reference = truth::parse_mode(&args.reference, args.samples)?;
    let reuse = sequence::Reuse::parse(&args.reuse)?;
    let timing = match args.timing.as_str() {
        "frame" => TimingMode::Frame,
        "stages" => TimingMode::Stages,
        v => return Err(crate::Error::param(format!("--timing {v}: use frame or stages")).into()),
    };
    let job = SequenceJob {
        scene: &scene,
        methods,
        frames: args.frames,
        animation,
        reference,
        cache: truth::Cache::default_for(args.no_cache),
        reuse,
        timing,
    };
    sequence::check(&job)?;
    crate::methods::check_lights(&scene, &job.methods)?;
    let ctx = GpuContext::with_request(gpu)?;
    // Every method's frame sizes before the first reference is traced.
    crate::methods::sizes::check_all(&ctx, &scene, &job.methods)?;
    log(&format!(
        "{} on {}",
        job.animation.describe(&scene),
        ctx.summary.name
    ));
    let outcome = sequence::run(&ctx, &job, &log)?;
    let html = sequence::write(&args.output.out, &outcome)?;
    print!("{}", tables::summary_table(&outcome.summaries));
    println!(
        "results: {}",
        args.output.out.join("frames.jsonl").display()
    );
    println!("report:  {}", html.display());
    Ok(())
}
