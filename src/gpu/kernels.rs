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

/// How a kernel reads shadow maps: the map access module prepended to it. The user's `maps` and
/// `raster` settings decide it (`MapAccess::of`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MapAccess {
    /// `Depth32Float` layers from the fixed-function raster (kernels/shared/maps_plain.wgsl).
    Depth,
    /// `R32Uint` layers of depth bits from the compute raster (kernels/shared/maps_words.wgsl).
    Words,
    /// A hybrid store (kernels/shared/maps_hybrid.wgsl).
    Hybrid,
}

impl MapAccess {
    /// The form map-reading kernels take for `maps`, over a raster that is compute or not. A hybrid
    /// store is read the same whichever raster filled it; its build reads the raster (`raster_of`).
    pub(crate) fn of(maps: MapKind, compute_raster: bool) -> Self {
        match maps {
            MapKind::Hybrid => MapAccess::Hybrid,
            MapKind::Plain => Self::raster_of(compute_raster),
        }
    }
    /// How the raster's own layers are read (moments, hybrid_build).
    pub(crate) fn raster_of(compute_raster: bool) -> Self {
        if compute_raster {
            MapAccess::Words
        } else {
            MapAccess::Depth
        }
    }
    /// Every form a kernel is built in.
    pub fn forms(k: &Kernel) -> &'static [MapAccess] {
        if k.reads_maps {
            &[MapAccess::Depth, MapAccess::Words, MapAccess::Hybrid]
        } else if k.reads_raster {
            &[MapAccess::Depth, MapAccess::Words]
        } else {
            &[MapAccess::Depth]
        }
    }
}

pub(crate) const PRELUDE: &str = include_str!("../../kernels/shared/common.wgsl");
/// Second prelude of the kernels the stage table marks `environment`: their structs and the BVH ray test.
pub(crate) const ENV_PRELUDE: &str = include_str!("../../kernels/shared/environment.wgsl");
/// The PCF family's tap patterns, for the kernels the stage table marks `pcf_taps`.
pub(crate) const PCF_TAPS: &str = include_str!("../../kernels/shared/pcf_taps.wgsl");
/// `map_depth` and friends over `Depth32Float` arrays (the default for every kernel).
pub(crate) const MAPS_PLAIN: &str = include_str!("../../kernels/shared/maps_plain.wgsl");
/// The same functions over the compute raster's R32Uint layers of depth bits.
pub(crate) const MAPS_WORDS: &str = include_str!("../../kernels/shared/maps_words.wgsl");
/// The same functions over a hybrid store (docs/hybrid.md), for kernels that read shadow maps.
pub(crate) const MAPS_HYBRID: &str = include_str!("../../kernels/shared/maps_hybrid.wgsl");
/// The comparison-sampler tap from four loads, for the forms without a depth texture.
pub(crate) const MAPS_LOADED_COMPARE: &str =
    include_str!("../../kernels/shared/maps_loaded_compare.wgsl");

/// Every stage with a kernel, with it (the stage table's kernels, in table order).
pub fn all() -> impl Iterator<Item = (Stage, Kernel)> {
    STAGES.iter().filter_map(|s| s.kernel.map(|k| (*s, k)))
}

/// Full source of a kernel for one map access form (`MapAccess::forms` lists a kernel's).
pub fn source_for(name: &str, maps: MapAccess) -> Result<String> {
    let k = Stage::named(name)
        .and_then(|s| s.kernel)
        .ok_or_else(|| Error::Kernel {
            name: name.into(),
            message: "no such kernel".into(),
        })?;
    if !MapAccess::forms(&k).contains(&maps) {
        return Err(Error::Kernel {
            name: name.into(),
            message: format!("reads no maps through map_depth: no {maps:?} form"),
        });
    }
    let access = match maps {
        MapAccess::Depth => MAPS_PLAIN.to_string(),
        MapAccess::Words => format!("{MAPS_WORDS}\n{MAPS_LOADED_COMPARE}"),
        MapAccess::Hybrid => format!("{MAPS_HYBRID}\n{MAPS_LOADED_COMPARE}"),
    };
    let environment = if k.environment { ENV_PRELUDE } else { "" };
    let taps = if k.pcf_taps { PCF_TAPS } else { "" };
    Ok(format!(
        "{PRELUDE}\n{access}\n{environment}\n{taps}\n{}",
        k.body
    ))
}

/// Parses and validates one kernel with naga (all validation flags), returning every error as text.
pub fn validate(name: &str) -> Result<(naga::Module, naga::valid::ModuleInfo)> {
    validate_for(name, MapAccess::Depth)
}

/// [`validate`] for one map access form.
pub fn validate_for(
    name: &str,
    maps: MapAccess,
) -> Result<(naga::Module, naga::valid::ModuleInfo)> {
    let src = source_for(name, maps)?;
    let module = naga::front::wgsl::parse_str(&src).map_err(|e| Error::Kernel {
        name: name.into(),
        message: e.emit_to_string(&src),
    })?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| Error::Kernel {
        name: name.into(),
        message: e.emit_to_string(&src),
    })?;
    Ok((module, info))
}
