//! `penumbra assets fetch`: registry meshes and panoramas into the cache, verified.

use anyhow::Result;
use penumbra_lab::assets;
use penumbra_lab::gpu::AdapterRequest;
use penumbra_lab::studies::Run;
use std::path::PathBuf;

#[derive(clap::Subcommand)]
pub enum AssetsCommand {
    /// Download and verify the assets into the cache ($PENUMBRA_CACHE, else ~/.cache/penumbra).
    Fetch(FetchArgs),
}

#[derive(clap::Args)]
pub struct FetchArgs {
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

impl Run for AssetsCommand {
    fn run(self, _gpu: &AdapterRequest) -> Result<()> {
        run(self)
    }
}

fn run(command: AssetsCommand) -> Result<()> {
    match command {
        AssetsCommand::Fetch(args) => fetch(args),
    }
}

fn fetch(args: FetchArgs) -> Result<()> {
    // Before anything is printed or fetched: the nearest existing folder on the way must be one.
    if let Some(cache) = &args.cache {
        if let Some(there) = cache
            .ancestors()
            .find(|a| !a.as_os_str().is_empty() && a.symlink_metadata().is_ok())
        {
            if !there.is_dir() {
                let what = if there == cache.as_path() {
                    "is a file".to_string()
                } else {
                    format!("{} is a file", there.display())
                };
                anyhow::bail!(
                    "--cache {}: {what}, not a folder: give a folder for the asset cache",
                    cache.display()
                );
            }
        }
    }
    let mut command = assets::FetchCommand {
        cache_dir: args.cache,
        check: args.check,
        ..Default::default()
    };
    if args.groups.iter().any(|g| g == "all") {
        command.groups = assets::Group::ALL.to_vec();
    } else if !args.groups.is_empty() {
        command.groups = args
            .groups
            .iter()
            .map(|g| g.parse())
            .collect::<Result<_, _>>()?;
    }
    command.run(&mut std::io::stdout())?;
    Ok(())
}
