//! One frame's size plan: the frame's own buffers and textures (G-buffer, V, the tile list, the
//! read-backs) and the method's (`ShadowMethod::size_needs`), from the scene's render settings
//! alone, checked against the device before anything is allocated (`Renderer::new`, and `compare`
//! before its reference). The frame driver allocates from the same numbers, and
//! lab/tests/large_frames.rs compares the plan with the buffers a renderer created.

use super::Method;
use crate::gpu::size_plan::{self, Bound, SizeNeed, SizePlan};
use crate::gpu::GpuContext;
use crate::scene::Scene;
use crate::stages::shade::{band_granule, band_rows as band_rows_for, TILE, TILE_LIST_HEADER};
use crate::Result;

/// Bytes per pixel of the CPU G-buffer: three Rgba32Float images.
const GBUFFER_TEXEL: u64 = 16;
const GBUFFER_IMAGES: u64 = 3;

/// V: one f32 per pixel, written by every method's last pass. `bands`: the method's passes bind it
/// a band of rows at a time (`stages::shade::Band`), so only the least band must fit a binding.
pub(crate) fn visibility(scene: &Scene, bands: bool, limits: &wgpu::Limits) -> SizeNeed {
    per_pixel_in(scene, "visibility", 4, bands, limits)
}

/// A per-pixel storage buffer of `bytes_per_pixel`, bound whole or (`bands`) by bands of rows.
pub(crate) fn per_pixel_in(
    scene: &Scene,
    what: &str,
    bytes_per_pixel: u64,
    bands: bool,
    limits: &wgpu::Limits,
) -> SizeNeed {
    let (w, h) = (scene.render.width as u64, scene.render.height as u64);
    if bands {
        let granule = band_granule(
            scene.render.width,
            limits.min_storage_buffer_offset_alignment,
        ) as u64;
        SizeNeed::rows(
            what,
            w * h * bytes_per_pixel,
            w * bytes_per_pixel * granule.min(h),
        )
    } else {
        SizeNeed::binding(what, w * h * bytes_per_pixel)
    }
}

/// Rows per band for `method`'s frame (0: one band): the most rows of its banded buffers that
/// one binding holds. Past the least band the plan has already refused the frame.
pub fn band_rows(scene: &Scene, method: &Method, limits: &wgpu::Limits) -> u32 {
    let r = &scene.render;
    let max_binding = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    let widest = method
        .0
        .size_needs(scene, limits)
        .iter()
        .filter(|n| matches!(n.bound, Bound::RowChunks { .. }))
        .map(|n| n.amount / r.height.max(1) as u64)
        .max();
    widest
        .and_then(|row| {
            band_rows_for(
                r.width,
                r.height,
                row,
                max_binding,
                limits.min_storage_buffer_offset_alignment,
            )
        })
        .unwrap_or(0)
}

/// A per-pixel storage buffer of `bytes_per_pixel`, bound whole.
pub(crate) fn per_pixel(scene: &Scene, what: &str, bytes_per_pixel: u64) -> SizeNeed {
    SizeNeed::binding(
        what,
        scene.render.width as u64 * scene.render.height as u64 * bytes_per_pixel,
    )
}

/// The geometry tile list (`ShadePass::tile_list_in_bands`): per band a header and one word per
/// 8x8 tile, each band's section padded to 256 bytes when there are several.
pub(crate) fn geometry_tiles_bytes(width: u32, height: u32, band_rows: u32) -> u64 {
    let tiles_x = width.div_ceil(TILE) as u64;
    if band_rows == 0 || band_rows >= height {
        return (TILE_LIST_HEADER as u64 + tiles_x * height.div_ceil(TILE) as u64) * 4;
    }
    height.div_ceil(band_rows) as u64
        * (TILE_LIST_HEADER as u64 + tiles_x * (band_rows / TILE) as u64).div_ceil(64)
        * 64
        * 4
}

/// How the one-line error names the resolution.
pub(crate) fn setting(scene: &Scene) -> String {
    let (w, h) = (scene.render.width, scene.render.height);
    if w == h {
        format!("resolution = {w} ({w}x{h})")
    } else {
        format!("resolution = {w}x{h} (render.width, render.height)")
    }
}

/// The shadow-map array `method` allocates on plain maps: as many maps as it keeps at once
/// (`ShadowMethod::shadow_maps`), split into arrays of what `shadow_map_budget_mib` and the layer
/// limit hold (`shadow_raster::maps_per_array`). None on hybrid maps (their own store), with no
/// maps, or where one map is over the budget (the raster refuses that with its own line).
pub(crate) fn shadow_map_array(
    scene: &Scene,
    method: &Method,
    limits: &wgpu::Limits,
) -> Option<SizeNeed> {
    let r = &scene.render;
    let maps = method.0.shadow_maps(scene);
    let map_bytes = (r.shadow_map_size as u64).pow(2) * 4;
    let by_budget = r.shadow_map_budget_mib as u64 * (1 << 20) / map_bytes.max(1);
    if r.maps == crate::scene::MapKind::Hybrid || maps == 0 || by_budget == 0 {
        return None;
    }
    let layers = (maps as u64)
        .min(by_budget)
        .min(limits.max_texture_array_layers as u64) as u32;
    let size = r.shadow_map_size;
    // The budget is what lets one array grow: lowering it splits the maps into smaller arrays.
    Some(
        SizeNeed::array(
            format!(
                "the shadow-map array ({layers} maps of {size}x{size}, shadow_map_size = {size})"
            ),
            layers as u64 * map_bytes,
            layers,
        )
        .sized_by(format!(
            "shadow_map_budget_mib = {}",
            r.shadow_map_budget_mib
        )),
    )
}

/// The shadow-map array of `layers` maps of `map_size` that a method sized at run time (regions'
/// classes, auto's grid) is about to allocate, through the plan's own check: one line naming the
/// budget, which lowering splits the maps into smaller arrays, instead of the device's out-of-memory.
pub(crate) fn check_run_time_array(
    ctx: &GpuContext,
    r: &crate::scene::RenderSettings,
    map_size: u32,
    layers: u32,
) -> Result<()> {
    let need = SizeNeed::array(
        format!("the shadow-map array ({layers} maps of {map_size}x{map_size}, a map size the method chose at run time)"),
        layers as u64 * (map_size as u64).pow(2) * 4,
        layers,
    )
    .sized_by(format!("shadow_map_budget_mib = {}", r.shadow_map_budget_mib));
    SizePlan {
        setting: String::new(),
        needs: vec![need],
        host_bytes: 0,
        host_setting: None,
    }
    .check(&ctx.bounds(), None)
}

/// Everything a frame of `method` on `scene` allocates, binds and reads back. `cpu_device`: the
/// device's memory is host memory (lavapipe), so it counts against MemAvailable too.
pub fn plan(scene: &Scene, method: &Method, limits: &wgpu::Limits, cpu_device: bool) -> SizePlan {
    let r = &scene.render;
    let (w, h) = (r.width as u64, r.height as u64);
    let pixels = w * h;
    let padded_row = (w * GBUFFER_TEXEL).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as u64)
        * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as u64;
    let mut needs = vec![
        SizeNeed::side("the G-buffer", w.max(h)),
        SizeNeed::side("a shadow map", r.shadow_map_size as u64)
            .sized_by(format!("shadow_map_size = {}", r.shadow_map_size)),
        SizeNeed::binding(
            "geometry tiles",
            geometry_tiles_bytes(r.width, r.height, band_rows(scene, method, limits)),
        ),
        SizeNeed::buffer(
            "the G-buffer read-back (one Rgba32Float image, rows padded to 256 bytes)",
            padded_row * h,
        ),
        SizeNeed::buffer("the V read-back", pixels * 4),
    ];
    let method_needs = method.0.size_needs(scene, limits);
    let array = shadow_map_array(scene, method, limits);
    // Host: the CPU G-buffer, one image's read-back in flight (staging and its copy), V three
    // times (buffer map, Vec, clamped copy) and the written images.
    let mut host =
        pixels * (GBUFFER_IMAGES * GBUFFER_TEXEL + 2 * padded_row / w.max(1) + 3 * 4 + 16);
    let mut host_setting = None;
    if cpu_device {
        // The G-buffer's images and depth, the shadow-map array, the method's buffers.
        host += pixels * (GBUFFER_IMAGES * GBUFFER_TEXEL + 4);
        host += method_needs
            .iter()
            .filter(|n| n.bound != size_plan::Bound::TextureSide)
            .map(|n| n.amount)
            .sum::<u64>();
        if let Some(a) = &array {
            // Where the maps are most of it, the budget is the setting to name.
            if a.amount > host {
                host_setting = a.setting.clone();
            }
            host += a.amount;
        }
    }
    needs.extend(method_needs);
    needs.extend(array);
    SizePlan {
        setting: setting(scene),
        needs,
        host_bytes: host,
        host_setting,
    }
}

/// [`plan`] on `ctx`'s device, checked: the one-line error, before any GPU work.
pub fn check(ctx: &GpuContext, scene: &Scene, method: &Method) -> Result<()> {
    let cpu = ctx.adapter.get_info().device_type == wgpu::DeviceType::Cpu;
    plan(scene, method, &ctx.limits(), cpu).check(&ctx.bounds(), size_plan::mem_available())
}

/// [`check`] for each method of a study, before its reference or any frame.
pub fn check_all(ctx: &GpuContext, scene: &Scene, methods: &[Method]) -> Result<()> {
    methods.iter().try_for_each(|m| check(ctx, scene, m))
}
