//! `penumbra info`: the adapter, why it was chosen, and the limits in use.

use anyhow::Result;
use penumbra_lab::gpu::{AdapterRequest, GpuContext};
use penumbra_lab::studies::Run;

#[derive(clap::Args)]
pub struct InfoArgs {}

impl Run for InfoArgs {
    fn run(self, gpu: &AdapterRequest) -> Result<()> {
        run(gpu)
    }
}

fn run(gpu: &AdapterRequest) -> Result<()> {
    let ctx = GpuContext::with_request(gpu)?;
    println!("{}", ctx.describe());
    Ok(())
}
