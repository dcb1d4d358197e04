//! `penumbra sweep`: compare over parameter grids from a TOML spec; the whole grid, one shard of
//! it (`--shard`), or K local shard processes merged into one set (`--jobs`).

use super::command::run_compare;
use super::run_args::RunArgs;
use crate::gpu::AdapterRequest;
use crate::record::{Provenance, SpecRef};
use crate::scene::Scene;
use crate::studies::compare::{methods_list, plan, sweep};
use crate::studies::shard::{self, Shard};
use anyhow::{Context, Result};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct SweepArgs {
    /// Sweep spec (TOML): `methods = [...]` and `[[grid]]` tables of parameter lists.
    #[arg(long)]
    spec: PathBuf,
    /// Run only shard INDEX of COUNT (from 0): a share of the grid balanced by estimated cost.
    #[arg(long, allow_hyphen_values = true, value_name = "INDEX/COUNT")]
    shard: Option<String>,
    /// Run the grid as K shard processes on this machine, then merge them into --out.
    #[arg(long, value_name = "K")]
    jobs: Option<u32>,
    /// Refuse a spec of more configurations than N (a guard against a grid that would run for hours).
    #[arg(long, value_name = "N", default_value_t = plan::DEFAULT_MAX_CONFIGS)]
    max_configs: usize,
    #[command(flatten)]
    run: RunArgs,
}

impl crate::studies::Run for SweepArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: SweepArgs, gpu: &AdapterRequest) -> Result<()> {
    args.run.output.checked()?;
    let specs = sweep::read_spec(&args.spec, args.max_configs)?;
    let methods = methods_list::parse_methods(&specs)?;
    let scene = Scene::load(&args.run.scene.scene, &args.run.sets.render()?)?;
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
        // A shard with no configuration would fail after the others ran: run one per configuration.
        let configs = u32::try_from(methods.len()).unwrap_or(u32::MAX);
        if k > configs {
            eprintln!(
                "--jobs {k}: the spec has {configs} configurations; running {configs} shards"
            );
        }
        return sweep_jobs(&args, k.min(configs), gpu);
    }
    let text = std::fs::read(&args.spec)
        .with_context(|| format!("{}: cannot read sweep spec", args.spec.display()))?;
    let costs: Vec<f64> = methods
        .iter()
        .map(|m| plan::estimated_cost(m, &scene))
        .collect();
    let mine = shard::assign(&costs, shard.count).swap_remove(shard.index as usize);
    if mine.is_empty() {
        anyhow::bail!(
            "--shard {shard}: the spec has {} configurations, too few for {} shards",
            methods.len(),
            shard.count
        );
    }
    let base = Provenance::of_scene("sweep", &scene, &args.run.sets.set, None);
    let spec = SpecRef {
        file: args.spec.display().to_string(),
        sha256: crate::record::provenance::sha256_hex(&text),
        configs: methods.len(),
        config: 0,
        shard: [shard.index, shard.count],
    };
    let provenance = mine
        .iter()
        .map(|&config| Provenance {
            spec: Some(SpecRef {
                config,
                ..spec.clone()
            }),
            ..base.clone()
        })
        .collect();
    if shard.count > 1 {
        let share: f64 = mine.iter().map(|&i| costs[i]).sum::<f64>() / costs.iter().sum::<f64>();
        eprintln!(
            "shard {shard}: {} of {} configurations, {:.0}% of the estimated cost",
            mine.len(),
            methods.len(),
            100.0 * share
        );
    }
    let methods = mine.iter().map(|&i| methods[i].clone()).collect();
    run_compare(methods, scene, provenance, args.run, None, gpu, true)
}

/// `sweep --jobs K`: this binary K times with `--shard i/K`, outputs in OUT/shards/i, then merged.
/// The merged set is written or nothing is: when a shard or the merge fails, the shard folders
/// this run made are removed again (the shards' own messages are above).
fn sweep_jobs(args: &SweepArgs, k: u32, gpu: &AdapterRequest) -> Result<()> {
    let shards = args.run.output.out.join("shards");
    let dirs: Vec<PathBuf> = (0..k).map(|i| shards.join(i.to_string())).collect();
    let made: Vec<PathBuf> = std::iter::once(&args.run.output.out)
        .chain([&shards])
        .chain(&dirs)
        .filter(|d| !d.exists())
        .cloned()
        .collect();
    let result = run_shards(args, &dirs, gpu);
    if result.is_err() {
        // Deepest first; a folder that holds anything else (a user's file) stays.
        for dir in made.iter().rev() {
            if dirs.contains(dir) {
                let _ = std::fs::remove_dir_all(dir);
            } else {
                let _ = std::fs::remove_dir(dir);
            }
        }
    }
    result
}

fn run_shards(args: &SweepArgs, dirs: &[PathBuf], gpu: &AdapterRequest) -> Result<()> {
    let exe = std::env::current_exe().context("cannot find this program to start the shards")?;
    let r = &args.run;
    let k = dirs.len();
    let mut children = Vec::new();
    for (i, dir) in dirs.iter().enumerate() {
        let mut cmd = std::process::Command::new(&exe);
        // The shards use the adapter this run was asked for, not the environment's default.
        cmd.arg("--backend").arg(gpu.backend.name());
        if let Some(name) = &gpu.name {
            cmd.arg("--adapter").arg(name);
        }
        cmd.arg("sweep")
            .arg("--spec")
            .arg(&args.spec)
            .arg("--shard")
            .arg(format!("{i}/{k}"));
        cmd.arg("--max-configs").arg(args.max_configs.to_string());
        cmd.args([
            "--scene",
            &r.scene.scene,
            "--repeats",
            &r.repeats.repeats.to_string(),
            "--reference",
            &r.reference,
            "--samples",
            &r.samples.to_string(),
        ]);
        for s in &r.sets.set {
            cmd.arg("--set").arg(s);
        }
        if r.no_cache {
            cmd.arg("--no-cache");
        }
        cmd.arg("--out")
            .arg(dir)
            .env("PENUMBRA_NO_PROGRESS", "1")
            .stdout(std::process::Stdio::null());
        children.push((
            i,
            cmd.spawn()
                .with_context(|| format!("cannot start shard {i}/{k}"))?,
        ));
    }
    let mut failed = Vec::new();
    for (i, mut child) in children {
        let status = child.wait().with_context(|| format!("shard {i}/{k}"))?;
        if !status.success() {
            failed.push(format!("{i}/{k}"));
        }
    }
    if !failed.is_empty() {
        anyhow::bail!(
            "sweep --jobs {k}: shards {} failed (their messages are above); nothing is written",
            failed.join(", ")
        );
    }
    let outcome = shard::merge::merge(dirs, &[])?;
    crate::studies::shard::command::write_merged(&r.output.out, &outcome)
}
