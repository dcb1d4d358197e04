//! `penumbra info`: the adapter, why it was chosen, and the limits in use.

use anyhow::Result;
use penumbra_lab::gpu::{AdapterRequest, GpuContext};

pub fn run(gpu: &AdapterRequest) -> Result<()> {
    let ctx = GpuContext::with_request(gpu)?;
    println!("{}", ctx.describe());
    Ok(())
}
