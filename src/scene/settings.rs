//! The `[render]` table of the scene format: resolution, shadow maps, bias and the rest, every key
//! overridable with `--set key=value` (docs/scene-format.md).

use serde::{Deserialize, Serialize};

/// Render settings; every key can be overridden with `--set key=value`.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields, default)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub shadow_map_size: u32,
    pub(crate) bias: BiasDef,
    pub cull: CullMode,
    pub ambient: f32,
    pub shadow_map_budget_mib: u32,
    pub(crate) self_shadow: SelfShadow,
    /// Shadow-map representation (docs/hybrid.md): `plain` depth arrays or `hybrid` merged maps.
    pub maps: MapKind,
    pub hybrid: HybridDef,
    /// Who rasterizes the shadow maps (docs/gpu-frame.md §7): the fixed-function `hardware` raster,
    /// the `compute` kernels, or `auto`, whichever this adapter runs faster on the scene.
    pub(crate) raster: RasterChoice,
}

pub use crate::gpu::kernels::MapKind;

/// The `raster` setting.
#[derive(Deserialize, Serialize, Debug, Clone, Copy, PartialEq, Eq, Default)]
#[serde(rename_all = "lowercase")]
pub(crate) enum RasterChoice {
    #[default]
    Hardware,
    Compute,
    Auto,
}

/// `maps = "hybrid"` settings. With them the raster size is `base` (it replaces `shadow_map_size`).
#[derive(Deserialize, Serialize, Debug, Clone, Copy, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct HybridDef {
    /// Full (raster) resolution per side; the coarse grid is base / 2^levels.
    pub base: u32,
    /// Merge levels, 1 or 2 (2048 → 1024 or 2048 → 512).
    pub levels: u32,
    /// Merge tolerance in 16-bit depth units (1/65535 of the [0, 1] depth range): a 2x2 block merges
    /// when each depth differs from the block's mean by at most eps. The seed's ε0 = 0.25.
    pub eps: f32,
}

impl Default for HybridDef {
    fn default() -> Self {
        Self {
            base: 2048,
            levels: 2,
            eps: 0.25,
        }
    }
}

/// How a surface shadows itself in the shadow-map methods.
#[derive(Deserialize, Serialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub(crate) enum SelfShadow {
    /// A light point below the surface's geometric tangent plane is blocked, as a ray finds it
    /// (the ground truth's rule): attached shadows are part of V.
    Facing,
    /// The depth test alone decides, as in classic shadow mapping and the seed: the attached shadow
    /// is left to the shading term max(0, n·l), and near the terminator bias reports points lit.
    Map,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 512,
            height: 512,
            shadow_map_size: 512,
            bias: BiasDef::default(),
            cull: CullMode::Back,
            ambient: 0.15,
            shadow_map_budget_mib: 512,
            self_shadow: SelfShadow::Facing,
            maps: MapKind::Plain,
            hybrid: HybridDef::default(),
            raster: RasterChoice::Hardware,
        }
    }
}

/// Shadow-map bias, in shadow-map texels at the receiver's depth (so independent of scene scale).
#[derive(Deserialize, Serialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields, default)]
pub struct BiasDef {
    pub constant: f32,
    pub slope: f32,
    pub normal_offset: f32,
    /// Cap on tan(angle) for the slope term: grazing angles would otherwise push the bias to infinity.
    pub max_slope: f32,
}

impl Default for BiasDef {
    fn default() -> Self {
        Self {
            constant: 0.5,
            slope: 0.5,
            normal_offset: 0.5,
            max_slope: 4.0,
        }
    }
}

#[derive(Deserialize, Serialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum CullMode {
    Back,
    Front,
    None,
}
