//! `penumbra report`: report.html and report.md again, from results.jsonl files.

use anyhow::Result;
use penumbra_lab::gpu::AdapterRequest;
use penumbra_lab::studies::Run;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct ReportArgs {
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

impl Run for ReportArgs {
    fn run(self, _gpu: &AdapterRequest) -> Result<()> {
        run(self)
    }
}

fn run(args: ReportArgs) -> Result<()> {
    if args.out.exists() && !args.out.is_dir() {
        anyhow::bail!("--out {}: is a file, not a folder", args.out.display());
    }
    let html = penumbra_lab::report::results::write_from_files_with_baseline(&args.results, args.baseline.as_deref(), &args.out)?;
    println!("report: {}", html.display());
    Ok(())
}
