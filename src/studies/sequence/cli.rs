//! The `sequence` command's flags and driver (the binary only parses and calls `run`).

use super::path::AnimationSpec;
use super::{SequenceJob, SequenceOutcome};
use crate::studies::compare::methods_list;
use crate::gpu::{AdapterRequest, GpuContext};
use crate::methods::is_method_key;
use crate::scene::Scene;
use crate::reference::truth;
use crate::{Error, Result};
use std::path::PathBuf;

#[derive(clap::Args, Debug, Clone)]
pub struct SequenceArgs {
    /// Built-in scene name or path to a scene TOML file.
    #[arg(long, default_value = "default")]
    pub scene: String,
    /// Methods, comma-separated as in compare (repeatable).
    #[arg(long, default_value = "hard,regular:n=17,adaptive")]
    pub methods: Vec<String>,
    /// Frames (2..=1000); each has its own CPU reference.
    #[arg(long, default_value_t = 24)]
    pub frames: u32,
    /// What moves: light, camera or occluder (one `[[mesh]]`, see --mesh).
    #[arg(long, default_value = "light")]
    pub animate: String,
    /// segment or circle (light, occluder); orbit or segment (camera). Default: segment, camera orbit.
    #[arg(long)]
    pub path: Option<String>,
    /// Segment: total displacement `x,y,z` (default: light 2 × edge_u; mesh 0.1 × scene diagonal along x).
    #[arg(long, allow_hyphen_values = true)]
    pub offset: Option<String>,
    /// Circle radius (default: light |edge_u|; mesh 0.05 × scene diagonal).
    #[arg(long)]
    pub radius: Option<f32>,
    /// Orbit angle in all, degrees (default 30).
    #[arg(long, allow_hyphen_values = true)]
    pub degrees: Option<f32>,
    /// The moving mesh for --animate occluder, counted from 1 in file order (default: the last).
    #[arg(long)]
    pub mesh: Option<u32>,
    /// Ground truth: `continuous` or `lattice`.
    #[arg(long, default_value = "continuous")]
    pub reference: String,
    /// M for the continuous reference (M×M samples).
    #[arg(long, default_value_t = 32)]
    pub samples: u32,
    /// Override a render setting, e.g. `--set resolution=256`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output folder.
    #[arg(long, default_value = "penumbra-out/sequence")]
    pub out: PathBuf,
    /// Trace the references even when the cache holds them.
    #[arg(long)]
    pub no_cache: bool,
}

/// `--set` pairs as render settings; a method parameter here is an error naming it.
pub fn render_sets(sets: &[String]) -> Result<Vec<(String, String)>> {
    let mut out = Vec::new();
    for s in sets {
        let (k, v) = s.split_once('=').ok_or_else(|| Error::Param(format!("--set {s}: expected KEY=VALUE")))?;
        let k = k.trim();
        if is_method_key(k) {
            return Err(Error::Param(format!("--set {k}=...: method parameters go in the method spec, e.g. `adaptive:{k}=...`")));
        }
        out.push((k.to_string(), v.trim().to_string()));
    }
    Ok(out)
}

/// Checks everything the user gave before the GPU starts, runs, writes the set; returns the outcome.
pub fn run(args: &SequenceArgs, gpu: &AdapterRequest, log: &dyn Fn(&str)) -> Result<(SequenceOutcome, PathBuf)> {
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
    super::check(&job)?;
    let ctx = GpuContext::with_request(gpu)?;
    log(&format!("{} on {}", job.animation.describe(&scene), ctx.summary.name));
    let outcome = super::run(&ctx, &job, log)?;
    let html = super::write(&args.out, &outcome)?;
    Ok((outcome, html))
}
