//! WGSL kernels, embedded at build time. Each stage's file gets the shared prelude and one map
//! access module prepended (plain concatenation, no preprocessor), so every kernel sees the same
//! `Gpu*` structs and reads shadow maps through the same `map_depth`.

use crate::gpu::stages::{Kernel, Stage, STAGES};
use crate::{Error, Result};

/// How every map-reading method stores its shadow maps.
#[derive(serde::Deserialize, serde::Serialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum MapKind {
    /// One `Depth32Float` layer of `shadow_map_size`² per map.
    Plain,
    /// Hybrid-resolution maps (seed 003): rasterized at `hybrid.base`², flat 2x2 blocks merged over
    /// `hybrid.levels` levels into a compact store with an index (docs/hybrid.md).
    Hybrid,
}

pub const PRELUDE: &str = include_str!("../../kernels/shared/common.wgsl");
/// Second prelude of the kernels the stage table marks `environment`: their structs and the BVH ray test.
pub const ENV_PRELUDE: &str = include_str!("../../kernels/shared/environment.wgsl");
/// The PCF family's tap patterns, for the kernels the stage table marks `pcf_taps`.
pub const PCF_TAPS: &str = include_str!("../../kernels/shared/pcf_taps.wgsl");
/// `map_depth` and friends over `Depth32Float` arrays (the default for every kernel).
pub const MAPS_PLAIN: &str = include_str!("../../kernels/shared/maps_plain.wgsl");
/// The same functions over a hybrid store (docs/hybrid.md), for kernels that read shadow maps.
pub const MAPS_HYBRID: &str = include_str!("../../kernels/shared/maps_hybrid.wgsl");

/// Every stage with a kernel, with it (the stage table's kernels, in table order).
pub fn all() -> impl Iterator<Item = (Stage, Kernel)> {
    STAGES.iter().filter_map(|s| s.kernel.map(|k| (*s, k)))
}

/// Full source of a kernel over plain maps: prelude + map access + body.
pub fn source(name: &str) -> Result<String> {
    source_for(name, MapKind::Plain)
}

/// Full source of a kernel for one map representation; only map-reading kernels have a hybrid form.
pub fn source_for(name: &str, maps: MapKind) -> Result<String> {
    let k = Stage::named(name)
        .and_then(|s| s.kernel)
        .ok_or_else(|| Error::Kernel { name: name.into(), message: "no such kernel".into() })?;
    let access = match maps {
        MapKind::Plain => MAPS_PLAIN,
        MapKind::Hybrid if k.reads_maps => MAPS_HYBRID,
        MapKind::Hybrid => return Err(Error::Kernel { name: name.into(), message: "does not read maps through map_depth: no hybrid form".into() }),
    };
    let environment = if k.environment { ENV_PRELUDE } else { "" };
    let taps = if k.pcf_taps { PCF_TAPS } else { "" };
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
