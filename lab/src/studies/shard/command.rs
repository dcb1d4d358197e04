//! `penumbra merge`: the shards of one sweep joined into one output set.

use crate::record::output_set;
use crate::studies::compare;
use crate::studies::shard;
use anyhow::Result;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct MergeArgs {
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

impl crate::studies::Run for MergeArgs {
    fn run(self, _gpu: &crate::gpu::AdapterRequest) -> Result<()> {
        run(self)
    }
}

fn run(args: MergeArgs) -> Result<()> {
    output_set::check(&args.out)?;
    let inputs: Vec<PathBuf> = args.dirs.iter().map(|d| d.join("results.jsonl")).collect();
    output_set::check_inputs(
        &args.out,
        &inputs
            .iter()
            .map(|p| ("DIR", p.as_path()))
            .collect::<Vec<_>>(),
    )?;
    let allow = shard::merge::parse_allow(&args.allow)?;
    let outcome = shard::merge::merge(&args.dirs, &allow)?;
    write_merged(&args.out, &outcome)
}

/// The merged set and its report (also the end of `sweep --jobs`).
pub fn write_merged(out: &Path, outcome: &shard::merge::MergeOutcome) -> Result<()> {
    let html = compare::write_set(out, &outcome.files, &outcome.rows)?;
    print!("{}", compare::table::render(&outcome.rows));
    for line in &outcome.inputs {
        println!("merged {line}");
    }
    println!("results: {}", out.join("results.jsonl").display());
    println!("report:  {}", html.display());
    Ok(())
}
