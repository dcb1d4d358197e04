//! WGSL kernels, embedded at build time. Each stage's file gets the shared prelude and one map
//! access module prepended (plain concatenation, no preprocessor), so every kernel sees the same
//! `Gpu*` structs and reads shadow maps through the same `map_depth`.

use crate::scene::MapKind;
use crate::{Error, Result};

pub const PRELUDE: &str = include_str!("../../kernels/shared/common.wgsl");
/// Second prelude of the environment kernels (`env_*`, `ssao`): their structs and the BVH ray test.
pub const ENV_PRELUDE: &str = include_str!("../../kernels/shared/environment.wgsl");
/// The PCF family's tap patterns, shared by `pcf` and `env_shadowmaps`.
pub const PCF_TAPS: &str = include_str!("../../kernels/shared/pcf_taps.wgsl");
/// `map_depth` and friends over `Depth32Float` arrays (the default for every kernel).
pub const MAPS_PLAIN: &str = include_str!("../../kernels/shared/maps_plain.wgsl");
/// The same functions over a hybrid store (docs/hybrid.md), for kernels that read shadow maps.
pub const MAPS_HYBRID: &str = include_str!("../../kernels/shared/maps_hybrid.wgsl");

/// One WGSL file: the stage name is the file name, the pass module, the CPU twin and the timing key.
pub struct KernelSource {
    pub name: &'static str,
    pub body: &'static str,
    /// Reads shadow maps through `map_depth`: built for either representation.
    pub reads_maps: bool,
}

macro_rules! kernel {
    ($name:literal) => {
        KernelSource { name: $name, body: include_str!(concat!("../../kernels/", $name, ".wgsl")), reads_maps: false }
    };
    ($name:literal, maps) => {
        KernelSource { name: $name, body: include_str!(concat!("../../kernels/", $name, ".wgsl")), reads_maps: true }
    };
}

pub const KERNELS: &[KernelSource] = &[
    kernel!("gbuffer"),
    kernel!("shadow_raster"),
    kernel!("shade", maps),
    kernel!("shadow_test", maps),
    kernel!("reproject_count"),
    kernel!("neighbourhood"),
    kernel!("quad_count"),
    kernel!("subdivide"),
    kernel!("compact"),
    kernel!("probe"),
    kernel!("cull"),
    kernel!("weights"),
    kernel!("pcf", maps),
    kernel!("pcss", maps),
    kernel!("moments"),
    kernel!("blur"),
    kernel!("reconstruct"),
    kernel!("env_trace"),
    kernel!("barycentrics"),
    kernel!("env_vertex_interp"),
    kernel!("env_count"),
    kernel!("env_split"),
    kernel!("env_shadowmaps"),
    kernel!("ssao"),
    kernel!("hybrid_build"),
];

/// Full source of a kernel over plain maps: prelude + map access + body.
pub fn source(name: &str) -> Result<String> {
    source_for(name, MapKind::Plain)
}

/// Full source of a kernel for one map representation; only map-reading kernels have a hybrid form.
pub fn source_for(name: &str, maps: MapKind) -> Result<String> {
    let k = KERNELS
        .iter()
        .find(|k| k.name == name)
        .ok_or_else(|| Error::Kernel { name: name.into(), message: "no such kernel".into() })?;
    let access = match maps {
        MapKind::Plain => MAPS_PLAIN,
        MapKind::Hybrid if k.reads_maps => MAPS_HYBRID,
        MapKind::Hybrid => return Err(Error::Kernel { name: name.into(), message: "does not read maps through map_depth: no hybrid form".into() }),
    };
    // The environment kernels add their own prelude (their structs and the BVH ray test).
    let environment = if k.name.starts_with("env_") || k.name == "ssao" { ENV_PRELUDE } else { "" };
    let taps = if matches!(k.name, "pcf" | "env_shadowmaps") { PCF_TAPS } else { "" };
    Ok(format!("{PRELUDE}\n{access}\n{environment}\n{taps}\n{}", k.body))
}

/// Parses and validates one kernel with naga (all validation flags), returning every error as text.
pub fn validate(name: &str) -> Result<(naga::Module, naga::valid::ModuleInfo)> {
    validate_for(name, MapKind::Plain)
}

/// [`validate`] for one map representation.
pub fn validate_for(name: &str, maps: MapKind) -> Result<(naga::Module, naga::valid::ModuleInfo)> {
    let src = source_for(name, maps)?;
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
