//! WGSL kernels, embedded at build time. Each stage's file gets the shared prelude prepended
//! (plain concatenation, no preprocessor), so every kernel sees the same `Gpu*` structs.

use crate::{Error, Result};

pub const PRELUDE: &str = include_str!("../kernels/shared/common.wgsl");

/// One WGSL file: the stage name is the file name, the pass module, the CPU twin and the timing key.
pub struct KernelSource {
    pub name: &'static str,
    pub body: &'static str,
}

macro_rules! kernel {
    ($name:literal) => {
        KernelSource { name: $name, body: include_str!(concat!("../kernels/", $name, ".wgsl")) }
    };
}

pub const KERNELS: &[KernelSource] = &[
    kernel!("gbuffer"),
    kernel!("shadow_raster"),
    kernel!("shade"),
    kernel!("shadow_test"),
    kernel!("reproject_count"),
    kernel!("neighbourhood"),
    kernel!("quad_count"),
    kernel!("subdivide"),
    kernel!("compact"),
    kernel!("probe"),
    kernel!("cull"),
    kernel!("weights"),
    kernel!("pcf"),
    kernel!("pcss"),
    kernel!("moments"),
    kernel!("blur"),
    kernel!("reconstruct"),
];

/// Full source of a kernel: prelude + body.
pub fn source(name: &str) -> Result<String> {
    let k = KERNELS
        .iter()
        .find(|k| k.name == name)
        .ok_or_else(|| Error::Kernel { name: name.into(), message: "no such kernel".into() })?;
    Ok(format!("{PRELUDE}\n{}", k.body))
}

/// Parses and validates one kernel with naga (all validation flags), returning every error as text.
pub fn validate(name: &str) -> Result<(naga::Module, naga::valid::ModuleInfo)> {
    let src = source(name)?;
    let module = naga::front::wgsl::parse_str(&src)
        .map_err(|e| Error::Kernel { name: name.into(), message: e.emit_to_string(&src) })?;
    let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
        .validate(&module)
        .map_err(|e| Error::Kernel { name: name.into(), message: e.emit_to_string(&src) })?;
    Ok((module, info))
}

/// Workgroup size of a compute entry point as naga reads it, so Rust dispatch sizes can be checked.
pub fn workgroup_size(name: &str, entry: &str) -> Result<[u32; 3]> {
    let (module, _) = validate(name)?;
    module
        .entry_points
        .iter()
        .find(|e| e.name == entry && e.stage == naga::ShaderStage::Compute)
        .map(|e| e.workgroup_size)
        .ok_or_else(|| Error::Kernel { name: name.into(), message: format!("no compute entry point `{entry}`") })
}
