//! `penumbra scenes`: every shipped scene, its triangles and meshes, and whether its assets are cached.

use anyhow::Result;
use penumbra_lab::gpu::AdapterRequest;
use penumbra_lab::scene::catalog;
use penumbra_lab::studies::Run;

#[derive(clap::Args)]
pub struct ScenesArgs {}

impl Run for ScenesArgs {
    fn run(self, _gpu: &AdapterRequest) -> Result<()> {
        run()
    }
}

fn run() -> Result<()> {
    println!(
        "{:22} {:>10}  {:9}  {:44}  description",
        "scene", "triangles", "assets", "meshes"
    );
    for e in catalog(None) {
        let tris = e.triangles.map_or("?".to_string(), |t| t.to_string());
        let assets = if e.missing.is_empty() {
            "present"
        } else {
            "missing"
        };
        println!(
            "{:22} {:>10}  {:9}  {:44}  {}",
            e.name,
            tris,
            assets,
            e.sources.join(" + "),
            e.description
        );
        if let Some(cmd) = penumbra_lab::assets::fetch_command(&e.fetch_groups) {
            println!("{:22} fetch with `{cmd}`", "");
        }
    }
    Ok(())
}
