//! `penumbra check`: the regression gate, results.jsonl against a baseline under tolerances.

use anyhow::Result;
use penumbra_lab::gpu::AdapterRequest;
use penumbra_lab::record::{regression, ResultRow};
use penumbra_lab::report::results::read_results;
use penumbra_lab::report::ReportError;
use penumbra_lab::studies::Run;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct CheckArgs {
    /// The baseline results.jsonl.
    #[arg(long, value_name = "OLD.jsonl")]
    baseline: PathBuf,
    /// The new results.jsonl.
    #[arg(value_name = "NEW.jsonl")]
    results: PathBuf,
    /// Tolerances: how much each metric may get worse, e.g. `time=+10%,rmse=+2%,maps=+0,psnr=-0.5`.
    #[arg(long, default_value = regression::DEFAULT_MAX)]
    max: String,
}

impl Run for CheckArgs {
    fn run(self, _gpu: &AdapterRequest) -> Result<()> {
        run(self)
    }
}

fn run(args: CheckArgs) -> Result<()> {
    let max = regression::parse_max(&args.max)?;
    let rows = |p: &Path, which: &str| -> Result<Vec<ResultRow>> {
        match read_results(p) {
            Ok(rows) => Ok(rows.into_iter().map(|l| l.row).collect()),
            Err(penumbra_lab::Error::Report(ReportError::Results { path, message })) => {
                anyhow::bail!("check: {which} {}: {message}", path.display())
            }
            Err(e) => Err(e.into()),
        }
    };
    let (old, new) = (
        rows(&args.baseline, "--baseline")?,
        rows(&args.results, "results")?,
    );
    let outcome = regression::check(&old, &new, &max);
    print!("{}", regression::render(&outcome));
    if outcome.regressions > 0 {
        anyhow::bail!(
            "check: {} regressions in {} against {}",
            outcome.regressions,
            args.results.display(),
            args.baseline.display()
        );
    }
    Ok(())
}
