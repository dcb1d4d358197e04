//! `penumbra frontier`: every fixed setting of one scene measured and judged, and the frontier of
//! error against time (docs/frontier.md).

use crate::gpu::{AdapterRequest, GpuContext};
use crate::record::run_files;
use crate::reference::truth;
use crate::scene::Scene;
use crate::studies::compare::plan;
use crate::studies::flags::{OutArgs, RepeatsArgs, SceneArgs, SetArgs};
use crate::studies::frontier::{self, files, grid, FrontierJob};
use anyhow::Result;

#[derive(clap::Args)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/frontier")))]
pub struct FrontierArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// The thinned grid (n in 2,3,4,5,6,8,11,17; plain maps 512 and 1024); automatic from 500,000 triangles.
    #[arg(long)]
    thin: bool,
    /// The full grid even on a scene of 500,000 triangles or more.
    #[arg(long)]
    full: bool,
    /// Regular grid sizes n (both layouts), replacing the grid's list, e.g. `--n 2,3,5`.
    #[arg(long, value_delimiter = ',')]
    n: Vec<String>,
    /// Plain map sizes, replacing the grid's list, e.g. `--sizes 512,1024`.
    #[arg(long, value_delimiter = ',')]
    sizes: Vec<String>,
    /// Hybrid maps as BASE/LEVELS (comma-separated), or `none`.
    #[arg(long, value_delimiter = ',', default_value = grid::DEFAULT_HYBRID)]
    hybrid: Vec<String>,
    /// The regular grids on plain maps cull each map's triangles (`cull = on`: the same V), as
    /// `regions` does; the hybrid groups' grids stay uncut.
    #[arg(long)]
    cull: bool,
    #[command(flatten)]
    repeats: RepeatsArgs,
    /// Ground truth: `continuous` or `lattice`.
    #[arg(long, default_value = "continuous")]
    reference: String,
    /// M for the continuous reference (M×M samples).
    #[arg(long, default_value_t = 32)]
    samples: u32,
    #[command(flatten)]
    sets: SetArgs,
    /// Error-budget targets (RMSE of V): `auto:target=T` for each, measured beside the plain-512
    /// settings and judged against the frontier of the fixed ones, e.g. `--budget 0.03,0.02,0.015`.
    #[arg(long, value_delimiter = ',')]
    budget: Vec<String>,
    /// Refuse a grid of more settings than N.
    #[arg(long, value_name = "N", default_value_t = plan::DEFAULT_MAX_CONFIGS)]
    max_configs: usize,
    #[command(flatten)]
    output: OutArgs,
    /// Trace the reference without the cache: nothing is read from it or stored in it.
    #[arg(long)]
    no_cache: bool,
    /// Certify every setting's RMSE from the exact truth at K drawn pixels (docs/certify.md).
    #[arg(long, value_name = "K")]
    certify: Option<usize>,
    /// With --certify: the bound holds with probability 1 − δ (default 0.05).
    #[arg(long, value_name = "δ")]
    delta: Option<f64>,
    /// Draw the front from the first windows' times: no n filled near the front, nothing timed
    /// again side by side (docs/frontier.md, "The second look").
    #[arg(long)]
    no_second_look: bool,
}

/// Render settings the grid itself sets for every setting.
const GRID_KEYS: [&str; 8] = [
    "shadow_map_size",
    "maps",
    "base",
    "levels",
    "eps",
    "hybrid.base",
    "hybrid.levels",
    "hybrid.eps",
];

impl crate::studies::Run for FrontierArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(self, gpu)
    }
}

fn run(args: FrontierArgs, gpu: &AdapterRequest) -> Result<()> {
    args.output.checked()?;
    let repeats = args.repeats.checked()?;
    let mode = truth::parse_mode(&args.reference, args.samples)?;
    let sets = args.sets.render()?;
    if let Some((k, v)) = sets
        .iter()
        .find(|(k, _)| GRID_KEYS.contains(&k.strip_prefix("render.").unwrap_or(k)))
    {
        anyhow::bail!("--set {k}={v}: the frontier sets the map size and kind of every setting itself; choose them with --sizes and --hybrid");
    }
    let n = (!args.n.is_empty())
        .then(|| grid::parse_n(&args.n))
        .transpose()?;
    let sizes = (!args.sizes.is_empty())
        .then(|| grid::parse_sizes(&args.sizes))
        .transpose()?;
    let hybrid = grid::parse_hybrid(&args.hybrid)?;
    let scene = Scene::load(&args.scene.scene, &sets)?;
    let certify = crate::studies::flags::certify_options(args.certify, args.delta, &scene)?;
    let thinning = grid::Thinning::choose(args.thin, args.full, scene.triangle_count())?;
    let mut axes = grid::Axes::of(&thinning);
    axes.n = n.unwrap_or(axes.n);
    axes.sizes = sizes.unwrap_or(axes.sizes);
    axes.hybrid = hybrid;
    axes.cull = args.cull;
    let budget = scene.render.shadow_map_budget_mib;
    plan::check_count(grid::count_of(&axes, budget), args.max_configs, "frontier")?;
    let mut groups = grid::settings(&axes, budget)?;
    let targets = grid::parse_budget(&args.budget)?;
    if !targets.is_empty() {
        // The budget chooses its own map sizes; it runs in the first plain group's window.
        let group = groups
            .iter_mut()
            .find(|g| g.maps.label().starts_with("plain"))
            .ok_or_else(|| anyhow::anyhow!("--budget needs a plain map size in --sizes"))?;
        // Each target for auto and, beside it, for the per-region method (docs/regions.md).
        for spec in targets
            .iter()
            .map(|t| format!("auto:target={t}"))
            .chain(targets.iter().map(|t| format!("regions:target={t}")))
        {
            group
                .methods
                .push(crate::methods::Method::parse(&spec, &[])?);
            group.specs.push(spec);
        }
    }
    let refused = grid::drop_refused(&mut groups, &scene, |s, m| {
        m.check_light(s).map_err(Into::into)
    });
    for (spec, why) in &refused {
        eprintln!("{spec} left out: {why}");
    }
    if let Some(size) = axes.sizes.iter().find(|&&s| !grid::local_fits(s, budget)) {
        eprintln!("adaptive scope=local left out from {size}² up: 289 maps do not fit shadow_map_budget_mib = {budget} (raise it with --set to run them)");
    }
    let ctx = GpuContext::with_request(gpu)?;
    // Every setting's frame sizes before the reference is traced or anything is written; a
    // setting over the device's limits is left out like local adaptive over the map budget.
    let mut unfit = grid::drop_refused(&mut groups, &scene, |s, m| {
        crate::methods::sizes::check(&ctx, s, m).map_err(Into::into)
    });
    // A map over the budget fails its setting at its first frame: left out before the run too.
    unfit.extend(grid::drop_refused(
        &mut groups,
        &scene,
        grid::one_map_over_budget,
    ));
    for line in left_out_lines(&unfit) {
        eprintln!("{line}");
    }
    groups.retain(|g| !g.methods.is_empty());
    if groups.is_empty() {
        let why = unfit
            .first()
            .map_or("the light refuses every method".to_string(), |(s, why)| {
                format!("{s}: {why}")
            });
        anyhow::bail!("frontier: no setting is left to run ({why})");
    }
    let all: Vec<_> = groups
        .iter()
        .flat_map(|g| g.methods.iter().cloned())
        .collect();
    let mut thinning = thinning.describe(&axes);
    // Recorded with the grid, so frontier.jsonl and frontier.md say what was ruled out.
    for (what, left) in [
        (
            format!("refusing the {} light", scene.emitter.kind().name()),
            &refused,
        ),
        (
            "over this device's limits or the map budget".to_string(),
            &unfit,
        ),
    ] {
        if !left.is_empty() {
            let specs: Vec<&str> = left.iter().map(|(s, _)| s.as_str()).collect();
            thinning = format!("{thinning}; left out, {what}: {}", specs.join(", "));
        }
    }
    // Each group's settings estimated at its own map size: a map's texels cost time too.
    let seconds: f64 = groups
        .iter()
        .map(|g| plan::estimated_seconds(&g.methods, &g.maps.apply(&scene, 0.25), repeats))
        .sum();
    eprintln!(
        "{} ({thinning})",
        plan::line_with(&all, seconds, &scene, repeats)
    );
    let job = FrontierJob {
        scene: &scene,
        groups,
        thinning,
        repeats,
        reference: mode,
        cache: truth::Cache::default_for(args.no_cache),
        certify,
        second_look: !args.no_second_look,
    };
    let lines = frontier::run(&ctx, &job, &|line| eprintln!("{line}"))?;
    run_files::write_files(&args.output.out, &files::files(&lines)?)?;
    let md = files::markdown(&lines);
    // The ladder only: the full table is in frontier.md.
    print!("{}", md.split("\n## Adaptive").next().unwrap_or(&md));
    println!(
        "\nfrontier: {}",
        args.output.out.join("frontier.jsonl").display()
    );
    println!(
        "report:   {}",
        args.output.out.join("report.html").display()
    );
    Ok(())
}

/// One line per map configuration and reason, as local adaptive's: `esm, vsm left out at plain
/// 4096: shadow_map_size = 4096: moments needs … bytes, over this device's …`.
fn left_out_lines(refused: &[(String, String)]) -> Vec<String> {
    let mut lines: Vec<(String, Vec<&str>, &str)> = Vec::new();
    for (setting, why) in refused {
        let (spec, maps) = setting.rsplit_once(" @ ").unwrap_or((setting, ""));
        match lines.iter_mut().find(|(m, _, w)| m == maps && *w == why) {
            Some((_, specs, _)) => specs.push(spec),
            None => lines.push((maps.to_string(), vec![spec], why)),
        }
    }
    lines
        .into_iter()
        .map(|(maps, specs, why)| format!("{} left out at {maps}: {why}", specs.join(", ")))
        .collect()
}
