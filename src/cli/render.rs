//! `penumbra render`: one scene, one method, one frame (after warm-up frames on the same renderer).

use super::split_sets;
use anyhow::Result;
use penumbra::frame;
use penumbra::gpu::timing::TimingMode;
use penumbra::gpu::{AdapterRequest, GpuContext};
use penumbra::methods::Method;
use penumbra::record::{output_set, run_files};
use penumbra::scene::Scene;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct RenderArgs {
    /// Built-in scene name or path to a scene TOML file.
    #[arg(long, default_value = "default", value_parser = crate::cli::utf8())]
    scene: String,
    /// hard | regular | adaptive, optionally with parameters: `adaptive:p_m=0,scope=local`.
    #[arg(long, default_value = "hard")]
    method: String,
    /// Output folder.
    #[arg(long, default_value = "penumbra-out")]
    out: PathBuf,
    /// Override a render setting or method parameter, e.g. `--set resolution=256 --set p_m=10`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// `stages`: wait after each stage to time it; `frame`: only the waits the method needs.
    #[arg(long, default_value = "stages", value_parser = ["stages", "frame"])]
    timing: String,
    /// Untimed frames first, on the same renderer: a device that compiles shaders at first use
    /// (lavapipe) would otherwise charge the compile to the stages. 0 times the very first frame.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1, value_parser = clap::value_parser!(u32).range(0..=100))]
    warm_up: u32,
}

pub fn run(args: RenderArgs, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&args.out)?;
    let (render_sets, method_sets) = split_sets(&args.set)?;
    let scene = Scene::load(&args.scene, &render_sets)?;
    let method = Method::parse(&args.method, &method_sets)?;
    let mode = if args.timing == "frame" { TimingMode::Frame } else { TimingMode::Stages };
    let ctx = GpuContext::with_request(gpu)?;
    let mut renderer = frame::Renderer::new(&ctx, &scene, &method)?;
    for _ in 0..args.warm_up {
        renderer.frame(TimingMode::Frame)?;
    }
    let result = renderer.frame(mode)?;
    let files = run_files::run_files(&scene, &method, &result, &ctx.summary, ctx.timestamps_trusted, args.warm_up)?;
    run_files::write_files(&args.out, &files)?;
    println!(
        "{}: {} on {} ({}x{}, {} shadow maps, {:.1} ms wall clock on {}, after {} warm-up frame{})",
        args.out.display(),
        method.label(),
        scene.name,
        scene.render.width,
        scene.render.height,
        result.output.shadow_maps,
        result.total_ms,
        ctx.summary.name,
        args.warm_up,
        if args.warm_up == 1 { "" } else { "s" }
    );
    for (name, _) in &files {
        println!("  {}", args.out.join(name).display());
    }
    Ok(())
}
