//! `penumbra assets fetch`: registry meshes and panoramas into the cache, verified.

use anyhow::Result;
use penumbra::scene::assets;
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

pub fn run(command: AssetsCommand) -> Result<()> {
    match command {
        AssetsCommand::Fetch(args) => fetch(args),
    }
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
