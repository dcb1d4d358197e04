//! `penumbra sequence`: N frames with a moving light, camera or mesh.

use super::render_sets;
use anyhow::Result;
use penumbra_lab::gpu::{AdapterRequest, GpuContext};
use penumbra_lab::reference::truth;
use penumbra_lab::scene::Scene;
use penumbra_lab::studies::compare::methods_list;
use penumbra_lab::studies::sequence::path::AnimationSpec;
use penumbra_lab::studies::sequence::{self, tables, SequenceJob};
use std::path::PathBuf;

#[derive(clap::Args, Debug, Clone)]
pub struct SequenceArgs {
    /// Built-in scene name or path to a scene TOML file.
    #[arg(long, default_value = "default", value_parser = crate::cli::utf8())]
    scene: String,
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
    /// Override a render setting, e.g. `--set resolution=256`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Output folder.
    #[arg(long, default_value = "penumbra-out/sequence")]
    out: PathBuf,
    /// Trace the references even when the cache holds them.
    #[arg(long)]
    no_cache: bool,
}

/// Checks everything the user gave before the GPU starts, runs, writes the set.
pub fn run(args: SequenceArgs, gpu: &AdapterRequest) -> Result<()> {
    let log = |line: &str| eprintln!("{line}");
    let methods = methods_list::parse_methods(&methods_list::split_specs(&args.methods)?)?;
    let scene = Scene::load(&args.scene, &render_sets(&args.set)?)?;
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
    let job = SequenceJob { scene: &scene, methods, frames: args.frames, animation, reference, cache: truth::Cache::default_for(args.no_cache) };
    sequence::check(&job)?;
    penumbra_lab::methods::check_lights(&scene, &job.methods)?;
    let ctx = GpuContext::with_request(gpu)?;
    // Every method's frame sizes before the first reference is traced.
    penumbra_lab::methods::sizes::check_all(&ctx, &scene, &job.methods)?;
    log(&format!("{} on {}", job.animation.describe(&scene), ctx.summary.name));
    let outcome = sequence::run(&ctx, &job, &log)?;
    let html = sequence::write(&args.out, &outcome)?;
    print!("{}", tables::summary_table(&outcome.summaries));
    println!("results: {}", args.out.join("frames.jsonl").display());
    println!("report:  {}", html.display());
    Ok(())
}
