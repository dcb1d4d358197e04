//! `penumbra seams`: a point light's cube-map seams, V's error near the face edges against the rest.

use crate::gpu::{AdapterRequest, GpuContext};
use crate::record::run_files;
use crate::reference::truth;
use crate::studies::compare::methods_list;
use crate::studies::flags::{OutArgs, SetArgs};
use crate::studies::lists::listed_once;
use crate::studies::seams::{self, SeamsJob};
use anyhow::Result;

#[derive(clap::Args)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/seams")))]
pub struct SeamsArgs {
    /// A scene with a point light (built-in name or TOML file).
    #[arg(long, value_parser = crate::studies::flags::utf8())]
    scene: String,
    /// Methods, as for compare (repeatable or comma-separated).
    #[arg(long, default_value = "hard,pcf,regular:n=8")]
    methods: Vec<String>,
    /// Shadow-map sizes (each cube face's side), comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "256,512")]
    map_sizes: Vec<u32>,
    /// The band: pixels whose direction lies within this many texels of a face edge.
    #[arg(long, allow_hyphen_values = true, default_value_t = 2.0)]
    band: f32,
    /// Continuous reference samples per side.
    #[arg(long, allow_hyphen_values = true, default_value_t = 32)]
    samples: u32,
    /// Trace the reference without the cache: nothing is read from it or stored in it.
    #[arg(long)]
    no_cache: bool,
    #[command(flatten)]
    sets: SetArgs,
    #[command(flatten)]
    output: OutArgs,
}

impl crate::studies::Run for SeamsArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: SeamsArgs, gpu: &AdapterRequest) -> Result<()> {
    args.output.checked()?;
    if !(args.band.is_finite() && args.band > 0.0 && args.band <= 64.0) {
        anyhow::bail!("--band {}: not in (0, 64] texels", args.band);
    }
    if args.map_sizes.is_empty() {
        anyhow::bail!("--map-sizes: give at least one size");
    }
    listed_once(
        "--map-sizes",
        args.map_sizes.iter().map(|s| (s.to_string(), *s)),
    )?;
    let methods = methods_list::parse_methods(&methods_list::split_specs(&args.methods)?)?;
    let sets = args.sets.render()?;
    // Each run's map size comes from --map-sizes and would silently win over this one.
    if let Some((k, v)) = sets
        .iter()
        .find(|(k, _)| k.strip_prefix("render.").unwrap_or(k) == "shadow_map_size")
    {
        anyhow::bail!("--set {k}={v}: seams runs each map size of --map-sizes; give the sizes there (--map-sizes {v})");
    }
    // Every map size, the scene's kind and each method's support are checked before the GPU starts.
    for &size in &args.map_sizes {
        let mut s = sets.clone();
        s.push(("shadow_map_size".into(), size.to_string()));
        let scene = crate::scene::Scene::load(&args.scene, &s)
            .map_err(|e| anyhow::anyhow!("--map-sizes {size}: {e}"))?;
        if scene.emitter.kind() != crate::scene::LightKind::Point {
            anyhow::bail!("--scene {}: its light is `{}`; the seams are a point light's cube faces (kind = \"point\")", args.scene, scene.emitter.kind().name());
        }
        crate::methods::check_lights(&scene, &methods)?;
    }
    let ctx = GpuContext::with_request(gpu)?;
    let job = SeamsJob {
        scene: args.scene.clone(),
        sets,
        map_sizes: args.map_sizes,
        methods,
        band: args.band,
        reference: truth::parse_mode("continuous", args.samples)?,
        cache: if args.no_cache {
            truth::Cache::Off
        } else {
            truth::Cache::default_for(false)
        },
    };
    let outcome = seams::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    run_files::write_files(&args.output.out, &outcome.files)?;
    print!("{}", seams::markdown(&outcome.rows));
    println!("adapter: {} ({})", ctx.summary.name, ctx.summary.backend);
    println!("study: {}", args.output.out.join("seams.json").display());
    Ok(())
}
