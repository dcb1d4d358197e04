//! `penumbra report`: report.html and report.md again, from results.jsonl files; or report.html of
//! a committed results folder (`penumbra report results/<name>`), its README and rows as tables.

use anyhow::Result;
use penumbra_lab::gpu::AdapterRequest;
use penumbra_lab::studies::Run;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct ReportArgs {
    /// results.jsonl files written by compare, sweep, merge or bench; or one results folder
    /// (README.md and rows as .csv/.jsonl, such as results/same-v).
    #[arg(required = true, value_name = "RESULTS.jsonl|FOLDER")]
    results: Vec<PathBuf>,
    /// Output folder for report.html, report.md and report_files/.
    #[arg(long, default_value = "penumbra-out")]
    out: PathBuf,
    /// Show each row's change against this baseline results.jsonl.
    #[arg(long, value_name = "OLD.jsonl")]
    baseline: Option<PathBuf>,
    /// Write the index of the results folders under the one folder given (each with its README's
    /// title) into its README.md, between its index marker lines, instead of a report.
    #[arg(long)]
    index: bool,
}

/// A path that does not end in `.jsonl` names a results folder.
fn is_folder(p: &std::path::Path) -> bool {
    p.extension().and_then(|x| x.to_str()) != Some("jsonl")
}

impl Run for ReportArgs {
    fn run(self, _gpu: &AdapterRequest) -> Result<()> {
        run(self)
    }
}

fn run(args: ReportArgs) -> Result<()> {
    if args.index {
        let [root] = args.results.as_slice() else {
            anyhow::bail!(
                "--index: takes one folder (results), not {} paths",
                args.results.len()
            )
        };
        if let Some(b) = &args.baseline {
            anyhow::bail!(
                "--baseline {}: --index writes an index, not a report",
                b.display()
            );
        }
        println!(
            "index: {}",
            penumbra_lab::report::results_index::write(root)?.display()
        );
        return Ok(());
    }
    if args.out.exists() && !args.out.is_dir() {
        anyhow::bail!("--out {}: is a file, not a folder", args.out.display());
    }
    let html = match args.results.as_slice() {
        [dir] if is_folder(dir) => {
            if let Some(b) = &args.baseline {
                anyhow::bail!(
                    "--baseline {}: compares results.jsonl rows, not a results folder ({})",
                    b.display(),
                    dir.display()
                );
            }
            penumbra_lab::report::results_folder::write(dir, &args.out)?
        }
        paths => {
            if let Some(dir) = paths.iter().find(|p| is_folder(p)) {
                anyhow::bail!(
                    "report {}: a results folder is reported alone, not with other files",
                    dir.display()
                );
            }
            penumbra_lab::report::results::write_from_files_with_baseline(
                paths,
                args.baseline.as_deref(),
                &args.out,
            )?
        }
    };
    println!("report: {}", html.display());
    Ok(())
}
