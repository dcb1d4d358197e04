//! The grove's tree: ez-tree's own code generates it under Node, three's OBJExporter writes it.
//! The script is embedded so the binary does not depend on where it is run from.

use std::path::Path;
use std::process::Command;

use super::error::{AssetError, Result};
use super::extract::unpack_npm;
use super::manifest::Package;
use super::tools::{self, NODE};

const GEN_TREE: &str = include_str!("../../../scripts/gen_tree.mjs");

/// The Node version the pinned OBJ digest was made with; V8's Math.sin/cos/pow may round
/// differently in another major version, so a mismatch there is worth saying.
pub(crate) const PINNED_NODE: &str = "v20.20.2";

/// Unpacks the npm archives as `work/node_modules/<name>` and writes the OBJ to `out`.
pub(crate) fn generate(
    preset: &str,
    packages: [(&Package, &Path); 2],
    work: &Path,
    out: &Path,
) -> Result<()> {
    let prefix = work.join("tree");
    for (i, (package, archive)) in packages.iter().enumerate() {
        let scratch = work.join(format!("unpack-{i}"));
        unpack_npm(
            archive,
            &scratch,
            &prefix.join("node_modules").join(package.name),
        )?;
    }
    let script = work.join("gen_tree.mjs");
    std::fs::write(&script, GEN_TREE).map_err(|source| AssetError::Io {
        path: script.clone(),
        source,
    })?;

    let mut command = Command::new(NODE.name);
    command.arg(&script).arg(&prefix).arg(preset).arg(out);
    tools::run(&mut command, &NODE)?;
    Ok(())
}

/// Appended to a digest mismatch of the generated OBJ.
pub(crate) fn mismatch_hint() -> String {
    let version = Command::new(NODE.name)
        .arg("--version")
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    format!(" (generated with node {version}; the pinned digest was made with node {PINNED_NODE})")
}
