//! `penumbra render`: one scene, one method, one frame (after warm-up frames on the same renderer).

use anyhow::Result;
use penumbra_lab::frame;
use penumbra_lab::frame::certify::{FrameCertifier, ProxyKind};
use penumbra_lab::gpu::timing::TimingMode;
use penumbra_lab::gpu::{AdapterRequest, GpuContext};
use penumbra_lab::methods::Method;
use penumbra_lab::record::run_files;
use penumbra_lab::scene::Scene;
use penumbra_lab::studies::flags::{param_pairs, render_sets_or, OutArgs, SceneArgs, SetArgs};
use penumbra_lab::studies::Run;

#[derive(clap::Args)]
pub struct RenderArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// hard | regular | adaptive, optionally with parameters: `adaptive:p_m=0,scope=local`.
    #[arg(long, default_value = "hard")]
    method: String,
    #[command(flatten)]
    output: OutArgs,
    // Method parameters go in --method or --param.
    #[command(flatten)]
    sets: SetArgs,
    /// A parameter of --method, e.g. `--param p_m=10` (the same as `--method adaptive:p_m=10`).
    #[arg(long = "param", value_name = "KEY=VALUE")]
    param: Vec<String>,
    /// `stages`: wait after each stage to time it; `frame`: only the waits the method needs.
    #[arg(long, default_value = "stages", value_parser = ["stages", "frame"])]
    timing: String,
    /// Untimed frames first, on the same renderer: a device that compiles shaders at first use
    /// (lavapipe) would otherwise charge the compile to the stages. 0 times the very first frame.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(0..=100))]
    warm_up: u32,
    /// Certify the frame's RMSE: the reference's exact truth at K pixels drawn by a truth-free
    /// proxy, and a one-sided bound at 1 − δ (run.json `certify`; docs/certify.md).
    #[arg(long, value_name = "K")]
    certify: Option<usize>,
    /// With --certify: the bound holds with probability 1 − δ (default 0.05).
    #[arg(long, value_name = "δ")]
    delta: Option<f64>,
}

impl Run for RenderArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: RenderArgs, gpu: &AdapterRequest) -> Result<()> {
    let out = args.output.checked()?;
    let name = args.method.split(':').next().unwrap_or_default();
    let render_sets = render_sets_or(&args.sets.set, Some(name), Some("--param"))?;
    let scene = Scene::load(&args.scene.scene, &render_sets)?;
    let method = Method::parse(&args.method, &param_pairs(&args.param)?)?;
    method.check_light(&scene)?;
    let certify = penumbra_lab::studies::flags::certify_options(args.certify, args.delta, &scene)?;
    let mode = if args.timing == "frame" {
        TimingMode::Frame
    } else {
        TimingMode::Stages
    };
    let ctx = GpuContext::with_request(gpu)?;
    let mut renderer = frame::Renderer::new(&ctx, &scene, &method)?;
    for _ in 0..args.warm_up {
        renderer.frame(TimingMode::Frame)?;
    }
    let result = renderer.frame(mode)?;
    // The certificate after the frame's clock, before anything is written.
    let certified = match certify {
        Some(options) => {
            penumbra_lab::studies::flags::certify_fits(&options, result.gbuffer.geometry_count())?;
            let mut certifier =
                FrameCertifier::new(&ctx, &scene, options, ProxyKind::SecondOpinion)?;
            Some(certifier.certify(&result)?)
        }
        None => None,
    };
    let certify_json = certified.as_ref().map(serde_json::to_value).transpose()?;
    let files = run_files::run_files(
        &scene,
        &method,
        &result,
        &ctx.summary,
        ctx.timestamps_trusted,
        args.warm_up,
        certify_json,
    )?;
    run_files::write_files(out, &files)?;
    println!(
        "{}: {} on {} ({}x{}, {} shadow maps, {:.1} ms wall clock on {}, after {} warm-up frame{})",
        out.display(),
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
    if let Some(c) = &certified {
        println!(
            "certified: {} (sampled {:.4}, {} bound; once per scene: second opinion {:.0} ms, BVH {:.0} ms)",
            penumbra_lab::record::Certified::of(c).line(),
            c.certificate.sampled_rmse,
            c.certificate.bound_kind.name(),
            c.second_opinion_ms,
            c.bvh_ms
        );
    }
    for (name, _) in &files {
        println!("  {}", out.join(name).display());
    }
    if let Some(n) = all_dark(&result) {
        eprintln!("warning: {}: V = 0 at all {n} geometry pixels: no light reaches any visible surface (is the light enclosed by a mesh?)", scene.origin);
    }
    Ok(())
}

/// The geometry pixel count when V is 0 at every one of them: a light shut in, which no scene check
/// sees up front (the frame is the cheap test).
fn all_dark(result: &frame::FrameResult) -> Option<usize> {
    let g = &result.gbuffer;
    let mut geometry = (0..result.visibility.len())
        .filter(|&i| g.is_geometry(i))
        .peekable();
    geometry.peek()?;
    let mut n = 0;
    for i in geometry {
        if result.visibility[i] != 0.0 {
            return None;
        }
        n += 1;
    }
    Some(n)
}
