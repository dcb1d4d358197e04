//! `penumbra methods`: every method with its family, parameters and defaults.

use anyhow::Result;
use penumbra_lab::gpu::AdapterRequest;
use penumbra_lab::studies::Run;

#[derive(clap::Args)]
pub struct MethodsArgs {}

impl Run for MethodsArgs {
    fn run(self, _gpu: &AdapterRequest) -> Result<()> {
        run()
    }
}

fn run() -> Result<()> {
    print!("{}", penumbra_lab::methods::describe());
    Ok(())
}
