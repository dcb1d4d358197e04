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
    print!("{}", describe());
    Ok(())
}

/// Every method with its family, one line on what it does, and its parameters, from the
/// engine's registry.
fn describe() -> String {
    let mut s = String::new();
    for m in penumbra_lab::methods::REGISTRY {
        s += &format!("{:<14} [{}] {}\n", m.name, m.family.title(), m.summary);
        for p in m.params {
            s += &format!("    {:<12} default {:<10} {}\n", p.key, p.default, p.help);
        }
    }
    s
}
