//! `penumbra bench`: benchmark suites; `--suite seed-table2` is seed 000's Table 2 on this machine.

use crate::gpu::{AdapterRequest, GpuContext};
use crate::methods::Method;
use crate::record::output_set;
use crate::report::results::{write_from_rows, LoadedRow};
use crate::studies::bench;
use crate::studies::flags::{OutArgs, RepeatsArgs, SetArgs};
use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(mut_arg("repeats", |a| a.default_value("5").help("Measured frames per method and scene, after one warm-up frame each")))]
#[command(mut_arg("out", |a| a.default_value("bench-out/seed-table2").help("Output folder for table2.md and results.jsonl")))]
pub struct BenchArgs {
    /// Which suite.
    #[arg(long, value_parser = ["seed-table2"])]
    suite: String,
    // Checked by the suite (at least 1).
    #[command(flatten)]
    repeats: RepeatsArgs,
    #[command(flatten)]
    output: OutArgs,
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
    /// The per-region method, set against the lattice and the fair grid; `none` leaves it out.
    #[arg(long, default_value = "regions")]
    regions: String,
    // Render settings for every scene file (named under the table).
    #[command(flatten)]
    sets: SetArgs,
    /// Keep each method's shadow maps from frame to frame (on) or render them every frame (off).
    /// Off by default: the suite times a still scene, whose repeated frames would keep every map,
    /// and its table compares frames that render their maps (docs/reuse.md).
    #[arg(long, default_value = "off", value_parser = ["on", "off"])]
    reuse: String,
}

impl crate::studies::Run for BenchArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: BenchArgs, gpu: &AdapterRequest) -> Result<()> {
    args.output.checked()?;
    let opts = bench::SuiteOptions {
        repeats: args.repeats.repeats,
        scenes_dir: args.scenes,
        cache: args.cache,
        adaptive: Method::parse(&args.adaptive, &[])?,
        regular: Method::parse(&args.regular, &[])?,
        regions: (args.regions != "none")
            .then(|| Method::parse(&args.regions, &[]))
            .transpose()?,
        only: args.only,
        sets: args.sets.render()?,
        reuse: args.reuse == "on",
    };
    let scenes = bench::prepare(&opts)?;
    let ctx = GpuContext::with_request(gpu)?;
    println!(
        "seed-table2 on {} ({} repeats after one warm-up frame per method)",
        ctx.summary.name, opts.repeats
    );
    // Progress on stdout; a failed setting's warning (and the count of them) on stderr.
    let results = bench::run_seed_table2(&ctx, &opts, scenes, &mut |line| {
        if line.starts_with("warning: ") {
            eprintln!("{line}")
        } else {
            println!("{line}")
        }
    })?;
    let files = [
        (
            "table2.md".to_string(),
            bench::table::markdown(&results).into_bytes(),
        ),
        (
            "results.jsonl".to_string(),
            bench::table::jsonl(&results)?.into_bytes(),
        ),
    ];
    // One set: the tables and the report with charts (from the rows that have error figures).
    let set = output_set::OutputSet::begin(&args.output.out)?;
    for (name, bytes) in &files {
        println!("  {}", set.write(name, bytes)?.display());
    }
    let rows: Vec<LoadedRow> = results
        .rows()
        .into_iter()
        .map(|row| LoadedRow {
            row,
            base: set.path().to_path_buf(),
        })
        .collect();
    if !rows.is_empty() {
        let _writing = set.writing();
        write_from_rows(&rows, set.path())?;
        println!("  {}", args.output.out.join("report.html").display());
    }
    set.commit()?;
    print!("{}", bench::table::markdown(&results));
    Ok(())
}
