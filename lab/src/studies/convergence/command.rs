//! `penumbra convergence`: one method's RMSE against the reference as its sample count grows,
//! with the fitted slope (convergence.json/.csv/.md).

use super::{ConvergenceJob, ConvergenceOutcome};
use crate::gpu::{AdapterRequest, GpuContext};
use crate::record::run_files;
use crate::reference::truth;
use crate::scene::Scene;
use crate::studies::flags::{OutArgs, SceneArgs, SetArgs};
use crate::studies::lists::listed_once;
use anyhow::Result;

/// One method's error against the reference as its sample count grows (about twice the shadow
/// maps each step), with the fitted slope of log RMSE against log maps (convergence.json/.csv/.md).
#[derive(clap::Args)]
#[command(mut_arg("out", |a| a.default_value("penumbra-out/convergence")))]
pub struct ConvergenceArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// The method, without the swept parameter, e.g. `regular:layout=jittered`.
    #[arg(long, default_value = "regular:layout=centred")]
    method: String,
    /// The parameter that sets its sample count.
    #[arg(long, default_value = "n")]
    key: String,
    /// The parameter's values, comma-separated, at least two.
    #[arg(long, value_delimiter = ',', default_value = "2,3,4,6,8,11,16")]
    values: Vec<String>,
    /// M for the continuous reference (M×M samples).
    #[arg(long, default_value_t = 32)]
    samples: u32,
    #[command(flatten)]
    sets: SetArgs,
    #[command(flatten)]
    output: OutArgs,
    /// Trace the reference without the cache: nothing is read from it or stored in it.
    #[arg(long)]
    no_cache: bool,
}

impl crate::studies::Run for ConvergenceArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        let out = self.output.checked()?;
        let values: Vec<String> = self
            .values
            .iter()
            .map(|v| v.trim().to_string())
            .filter(|v| !v.is_empty())
            .collect();
        if values.len() < 2 {
            anyhow::bail!(
                "--values {}: give at least two values to fit a slope",
                self.values.join(",")
            );
        }
        let name = self.method.split(':').next().unwrap_or_default().trim();
        if !crate::methods::REGISTRY.iter().any(|m| m.name == name) {
            let known: Vec<&str> = crate::methods::REGISTRY.iter().map(|m| m.name).collect();
            anyhow::bail!(
                "--method {}: unknown method `{name}` (known: {})",
                self.method,
                known.join(", ")
            );
        }
        if !crate::methods::methods_with_param(&self.key).contains(&name) {
            anyhow::bail!(
                "--key {}: not a parameter of method {name} (`penumbra methods` lists them)",
                self.key
            );
        }
        let given = self.method.split_once(':').map_or("", |(_, p)| p);
        if given
            .split(',')
            .any(|kv| kv.split('=').next().unwrap_or_default().trim() == self.key)
        {
            anyhow::bail!(
                "--method {}: sets {} itself; leave it to --values",
                self.method,
                self.key
            );
        }
        let scene = Scene::load(&self.scene.scene, &self.sets.render()?)?;
        let reference = truth::parse_mode("continuous", self.samples)?;
        let job = ConvergenceJob {
            scene: &scene,
            spec: self.method.clone(),
            key: self.key.clone(),
            values,
            reference,
            cache: truth::Cache::default_for(self.no_cache),
        };
        // Every value parsed, given once and accepted by the light before the GPU starts.
        let methods = super::methods(&job)?;
        listed_once(
            "--values",
            job.values.iter().zip(methods.iter().map(|m| m.label())),
        )?;
        let ctx = GpuContext::with_request(gpu)?;
        crate::methods::sizes::check_all(&ctx, &scene, &methods)?;
        let outcome: ConvergenceOutcome = super::run(&ctx, &job, &|line| eprintln!("{line}"))?;
        run_files::write_files(out, &super::files(&outcome)?)?;
        print!("{}", super::markdown(&outcome));
        println!("study: {}", out.join("convergence.json").display());
        Ok(())
    }
}
