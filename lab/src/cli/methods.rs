//! `penumbra methods`: every method with its family, parameters and defaults.

use anyhow::Result;

pub fn run() -> Result<()> {
    print!("{}", penumbra_lab::methods::describe());
    Ok(())
}
