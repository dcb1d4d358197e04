//! `penumbra framing`: maps and error against the penumbra's width on screen, over scenes,
//! resolutions and light sizes.

use crate::gpu::{AdapterRequest, GpuContext};
use crate::record::run_files;
use crate::reference::truth;
use crate::scene::{light_checks, Scene, MAX_SUN_DIAMETER_DEG};
use crate::studies::compare::methods_list;
use crate::studies::flags::{OutArgs, RepeatsArgs, SetArgs};
use crate::studies::framing::{self, FramingJob};
use crate::studies::lists::listed_once;
use anyhow::{Context, Result};

#[derive(clap::Args)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/framing")))]
#[command(mut_arg("repeats", |a| a.default_value("1")))]
pub struct FramingArgs {
    /// Scenes (built-in names or TOML files), repeatable or comma-separated.
    #[arg(long = "scene", value_delimiter = ',', required = true, value_parser = crate::studies::flags::utf8())]
    scenes: Vec<String>,
    /// Square screen sizes in pixels, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "128,256,512")]
    resolutions: Vec<u32>,
    /// Factors on the light's edges, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "1")]
    light_scales: Vec<f32>,
    /// Methods, as for compare (repeatable).
    #[arg(
        long,
        default_value = "regular:n=17,regular:n=9,layout=centred,adaptive:preset=seed,adaptive:preset=balanced"
    )]
    methods: Vec<String>,
    #[command(flatten)]
    repeats: RepeatsArgs,
    #[command(flatten)]
    sets: SetArgs,
    #[command(flatten)]
    output: OutArgs,
}

impl crate::studies::Run for FramingArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: FramingArgs, gpu: &AdapterRequest) -> Result<()> {
    args.output.checked()?;
    let specs = methods_list::split_specs(&args.methods)?;
    let methods = methods_list::parse_methods(&specs)?;
    let sets = args.sets.render()?;
    listed_once("--scene", args.scenes.iter().map(|s| (s, s.trim())))?;
    listed_once(
        "--resolutions",
        args.resolutions.iter().map(|r| (r.to_string(), *r)),
    )?;
    listed_once(
        "--light-scales",
        args.light_scales.iter().map(|k| (k.to_string(), *k)),
    )?;
    let scenes = args
        .scenes
        .iter()
        .map(|s| Scene::load(s, &sets))
        .collect::<penumbra::Result<Vec<_>>>()?;
    // Each method against each scene's light, before any reference is traced.
    for (scene, name) in scenes.iter().zip(&args.scenes) {
        for (spec, method) in specs.iter().zip(&methods) {
            method
                .check_light(scene)
                .with_context(|| format!("--methods {spec} on --scene {name}"))?;
        }
    }
    if let Some(r) = args.resolutions.iter().find(|&&r| !(8..=4096).contains(&r)) {
        anyhow::bail!("--resolutions: {r} is not in 8..=4096");
    }
    if let Some(k) = args
        .light_scales
        .iter()
        .find(|&&k| !(k.is_finite() && k > 0.0 && k <= 100.0))
    {
        anyhow::bail!("--light-scales: {k} is not in (0, 100]");
    }
    // A sun scaled past the widest sun a scene may state is a sky, not a sun.
    for scene in &scenes {
        if let crate::scene::Emitter::Sun(sun) = scene.emitter {
            if let Some(k) = args
                .light_scales
                .iter()
                .find(|&&k| sun.angular_diameter_deg * k > MAX_SUN_DIAMETER_DEG)
            {
                anyhow::bail!(
                    "--light-scales: {k} makes {}'s sun {}° across (light.angular_diameter_deg = {} times {k}), over the {MAX_SUN_DIAMETER_DEG}° a sun may be",
                    scene.name,
                    sun.angular_diameter_deg * k,
                    sun.angular_diameter_deg
                );
            }
        }
    }
    // Each scaled light through the scene file's light checks, before any reference is traced: a
    // light scaled past ten scene diagonals, or a sphere scaled into a mesh, would measure nothing.
    for (scene, name) in scenes.iter().zip(&args.scenes) {
        for &k in &args.light_scales {
            light_checks::check_scene(&framing::configure(scene, scene.render.width, k))
                .with_context(|| format!("--light-scales {k} on --scene {name}"))?;
        }
    }
    let repeats = args.repeats.checked()?;
    let ctx = GpuContext::with_request(gpu)?;
    let job = FramingJob {
        scenes,
        resolutions: args.resolutions,
        light_scales: args.light_scales,
        methods,
        repeats,
        reference: truth::parse_mode("continuous", 32)?,
        cache: truth::Cache::default_for(false),
    };
    let outcome = framing::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    run_files::write_files(&args.output.out, &outcome.files)?;
    print!("{}", framing::markdown(&outcome.rows));
    println!(
        "adapter: {} ({}); wall clock",
        ctx.summary.name, ctx.summary.backend
    );
    println!("study: {}", args.output.out.join("framing.md").display());
    Ok(())
}
