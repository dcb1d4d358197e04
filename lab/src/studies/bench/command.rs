//! `penumbra bench`: benchmark suites; `--suite seed-table2` is seed 000's Table 2 on this machine.

use anyhow::Result;
use penumbra_lab::gpu::{AdapterRequest, GpuContext};
use penumbra_lab::methods::Method;
use penumbra_lab::record::output_set;
use penumbra_lab::report::results::{write_from_rows, LoadedRow};
use penumbra_lab::studies::bench;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct BenchArgs {
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
    /// Override a render setting in every scene file, e.g. `--set raster=auto` (named under the table).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

pub fn run(args: BenchArgs, gpu: &AdapterRequest) -> Result<()> {
    output_set::check(&args.out)?;
    let opts = bench::SuiteOptions {
        repeats: args.repeats,
        scenes_dir: args.scenes,
        cache: args.cache,
        adaptive: Method::parse(&args.adaptive, &[])?,
        regular: Method::parse(&args.regular, &[])?,
        only: args.only,
        sets: super::render_sets(&args.set)?,
    };
    let scenes = bench::prepare(&opts)?;
    let ctx = GpuContext::with_request(gpu)?;
    println!("seed-table2 on {} ({} repeats after one warm-up frame per method)", ctx.summary.name, opts.repeats);
    // Progress on stdout; a failed setting's warning (and the count of them) on stderr.
    let results = bench::run_seed_table2(&ctx, &opts, scenes, &mut |line| if line.starts_with("warning: ") { eprintln!("{line}") } else { println!("{line}") })?;
    let files = [
        ("table2.md".to_string(), bench::table::markdown(&results).into_bytes()),
        ("results.jsonl".to_string(), bench::table::jsonl(&results)?.into_bytes()),
    ];
    // One set: the tables and the report with charts (from the rows that have error figures).
    let set = output_set::OutputSet::begin(&args.out)?;
    for (name, bytes) in &files {
        println!("  {}", set.write(name, bytes)?.display());
    }
    let rows: Vec<LoadedRow> = results.rows().into_iter().map(|row| LoadedRow { row, base: set.path().to_path_buf() }).collect();
    if !rows.is_empty() {
        write_from_rows(&rows, set.path())?;
        println!("  {}", args.out.join("report.html").display());
    }
    set.commit()?;
    print!("{}", bench::table::markdown(&results));
    Ok(())
}
