//! regions: per screen region, its geometry and penumbra pixels, finest footprint, narrowest
//! penumbra and receiver box (`measure`, a blocker search on the centre map); the target's scale
//! (`total`); then each geometry tile's samples per side and class, and the classes' tile lists,
//! texel needs and receiver boxes (`classify`). docs/regions.md derives the rule.

use super::shade::{GeometryTiles, TILE, TILE_LIST_HEADER};
use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP, PIXEL_WORKGROUP};
use crate::gpu::kernels::MapAccess;
use crate::gpu::stages::bind;
use crate::gpu::{readback, GpuContext, Stage};
use crate::render::gbuffer::GBuffer;
use crate::Result;
use bytemuck::{Pod, Zeroable};

/// Words per region (`REGION_WORDS` in kernels/regions.wgsl): geometry pixels, penumbra pixels,
/// the finest footprint and the narrowest penumbra over depth, the receivers' box (min xyz, max
/// xyz), the last eight as [`ordered`] bits.
pub const REGION_WORDS: usize = 10;
/// Words per class (`CLASS_WORDS`): tiles, the finest texel, the receivers' box.
pub const CLASS_WORDS: usize = 8;
/// Fixed-point units per 1 of the weights' sum (`WEIGHT_SCALE`).
pub const WEIGHT_SCALE: f32 = 16.0;
/// The sampling error's order in n (`SAMPLING_ORDER`; docs/error-estimate.md measured 1.5).
pub const SAMPLING_ORDER: f32 = 1.5;
/// Most classes (the ladder's length).
pub(crate) const MAX_CLASSES: usize = 16;

/// The kernel's uniform (`RegionsParams` in kernels/regions.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct RegionsParams {
    pub regions_x: u32,
    pub region: u32,
    pub ladder_len: u32,
    pub max_n: u32,
    pub target: f32,
    pub blocker_taps: u32,
    pub max_radius: f32,
    pub section_words: u32,
    pub light_u: f32,
    pub light_v: f32,
    pub max_tiles: u32,
    pub region_count: u32,
    pub ladder: [u32; MAX_CLASSES],
}

/// A float as a u32 whose unsigned order is the float's (`ordered` in the kernel).
pub fn ordered(x: f32) -> u32 {
    let b = x.to_bits();
    if b & 0x8000_0000 != 0 {
        !b
    } else {
        b | 0x8000_0000
    }
}

/// The float of [`ordered`] bits.
pub fn unordered(k: u32) -> f32 {
    f32::from_bits(if k & 0x8000_0000 != 0 {
        k & 0x7fff_ffff
    } else {
        !k
    })
}

/// A region's words before any pixel: no pixels, no footprint or penumbra, an empty box.
pub fn empty_region() -> [u32; REGION_WORDS] {
    [
        0,
        0,
        u32::MAX,
        u32::MAX,
        u32::MAX,
        u32::MAX,
        u32::MAX,
        0,
        0,
        0,
    ]
}

/// A class's words before any tile: no tiles, no texel need, an empty box.
pub(crate) fn empty_class() -> [u32; CLASS_WORDS] {
    [0, u32::MAX, u32::MAX, u32::MAX, u32::MAX, 0, 0, 0]
}

/// What `record` reads: the frame uniform, the screen's G-buffer and geometry tiles, and the centre
/// map (`samples[0]`, layer 0 of `maps`).
#[derive(Clone, Copy)]
pub(crate) struct RegionsInputs<'a> {
    pub(crate) frame: &'a wgpu::Buffer,
    pub(crate) gbuffer: &'a GBuffer,
    pub(crate) tiles: &'a GeometryTiles,
    pub(crate) samples: &'a wgpu::Buffer,
    pub(crate) maps: &'a wgpu::TextureView,
}

/// The passes and the buffers they fill, sized for one screen and ladder.
pub(crate) struct RegionsPass {
    measure: ComputeKernel,
    total: ComputeKernel,
    classify: ComputeKernel,
    pub(crate) params: RegionsParams,
    params_buffer: wgpu::Buffer,
    /// REGION_WORDS per region.
    pub(crate) regions: wgpu::Buffer,
    /// CLASS_WORDS per class.
    pub(crate) classes: wgpu::Buffer,
    /// The weights' sum (fixed point) and the geometry pixels.
    pub(crate) totals: wgpu::Buffer,
    /// A section of `section_words` per class: shade's tile-list header, then the tiles.
    pub(crate) class_tiles: wgpu::Buffer,
    /// A section per group of classes (the method's cost model joins classes): their lists one
    /// after another, so a group's shade is one pass per block.
    pub(crate) group_tiles: wgpu::Buffer,
    /// What `regions`, `classes` and `class_tiles` hold before a frame.
    regions_init: wgpu::Buffer,
    classes_init: wgpu::Buffer,
    tiles_init: wgpu::Buffer,
    pub(crate) region_count: u32,
}

impl RegionsPass {
    /// `params`' ladder, step and search are the caller's; the sizes come from `gbuffer`.
    pub(crate) fn new(
        ctx: &GpuContext,
        maps: MapAccess,
        gbuffer: &GBuffer,
        mut params: RegionsParams,
    ) -> Result<Self> {
        let (w, h) = (gbuffer.width, gbuffer.height);
        params.regions_x = groups(w, params.region);
        let region_count = params.regions_x * groups(h, params.region);
        params.region_count = region_count;
        params.max_tiles = groups(w, TILE) * groups(h, TILE);
        // Sections start at 256-byte offsets, so shade binds each as a tile list of its own.
        params.section_words = (TILE_LIST_HEADER as u32 + params.max_tiles).div_ceil(64) * 64;
        let classes = params.ladder_len as usize;
        let regions_words: Vec<u32> = (0..region_count).flat_map(|_| empty_region()).collect();
        let classes_words: Vec<u32> = (0..classes).flat_map(|_| empty_class()).collect();
        let mut tiles_words = vec![0u32; classes * params.section_words as usize];
        for c in 0..classes {
            tiles_words[c * params.section_words as usize + 1] = 1;
            tiles_words[c * params.section_words as usize + 2] = 1;
        }
        let indirect = wgpu::BufferUsages::INDIRECT;
        Ok(Self {
            measure: ComputeKernel::new_for(ctx, Stage::REGIONS, "measure", maps)?,
            total: ComputeKernel::new_for(ctx, Stage::REGIONS, "total", maps)?,
            classify: ComputeKernel::new_for(ctx, Stage::REGIONS, "classify", maps)?,
            totals: readback::zeroed_storage(ctx, "region totals", 8),
            params_buffer: readback::uniform_buffer(ctx, "regions params", &params),
            regions: readback::storage_buffer(
                ctx,
                "regions",
                &regions_words,
                wgpu::BufferUsages::empty(),
            ),
            classes: readback::storage_buffer(
                ctx,
                "region classes",
                &classes_words,
                wgpu::BufferUsages::empty(),
            ),
            class_tiles: readback::storage_buffer(ctx, "class tiles", &tiles_words, indirect),
            group_tiles: readback::storage_buffer(ctx, "group tiles", &tiles_words, indirect),
            regions_init: readback::storage_buffer(
                ctx,
                "regions init",
                &regions_words,
                wgpu::BufferUsages::empty(),
            ),
            classes_init: readback::storage_buffer(
                ctx,
                "region classes init",
                &classes_words,
                wgpu::BufferUsages::empty(),
            ),
            tiles_init: readback::storage_buffer(
                ctx,
                "class tiles init",
                &tiles_words,
                wgpu::BufferUsages::empty(),
            ),
            params,
            region_count,
        })
    }

    /// Resets the buffers, then measures every pixel against the centre map (`inputs.samples[0]`,
    /// in `inputs.maps`) and classifies the frame's geometry tiles.
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        inputs: &RegionsInputs,
    ) {
        let RegionsInputs {
            frame,
            gbuffer,
            tiles,
            samples,
            maps,
        } = *inputs;
        enc.copy_buffer_to_buffer(&self.regions_init, 0, &self.regions, 0, self.regions.size());
        enc.copy_buffer_to_buffer(&self.classes_init, 0, &self.classes, 0, self.classes.size());
        enc.copy_buffer_to_buffer(
            &self.tiles_init,
            0,
            &self.class_tiles,
            0,
            self.class_tiles.size(),
        );
        enc.clear_buffer(&self.totals, 0, None);
        self.measure.dispatch(
            ctx,
            enc,
            bind::regions::Measure {
                frame: frame.as_entire_binding(),
                params: self.params_buffer.as_entire_binding(),
                samples: samples.as_entire_binding(),
                gbuffer_position: wgpu::BindingResource::TextureView(&gbuffer.position_view),
                gbuffer_normal: wgpu::BindingResource::TextureView(&gbuffer.normal_view),
                shadow_maps: wgpu::BindingResource::TextureView(maps),
                regions: self.regions.as_entire_binding(),
            },
            Dispatch::Direct([
                groups(gbuffer.width, PIXEL_WORKGROUP[0]),
                groups(gbuffer.height, PIXEL_WORKGROUP[1]),
                1,
            ]),
        );
        self.total.dispatch(
            ctx,
            enc,
            bind::regions::Total {
                params: self.params_buffer.as_entire_binding(),
                regions: self.regions.as_entire_binding(),
                totals: self.totals.as_entire_binding(),
            },
            Dispatch::Direct([groups(self.region_count, LINE_WORKGROUP[0]), 1, 1]),
        );
        self.classify.dispatch(
            ctx,
            enc,
            bind::regions::Classify {
                frame: frame.as_entire_binding(),
                params: self.params_buffer.as_entire_binding(),
                regions: self.regions.as_entire_binding(),
                tile_list: tiles.list.as_entire_binding(),
                classes: self.classes.as_entire_binding(),
                class_tiles: self.class_tiles.as_entire_binding(),
                totals: self.totals.as_entire_binding(),
            },
            Dispatch::Direct([groups(self.params.max_tiles, LINE_WORKGROUP[0]), 1, 1]),
        );
    }

    /// Section `g` of the group lists holds `classes`' tiles (class, tile count as read back), one
    /// list after another: a header written from the counts, then one copy per class. Returns it as
    /// shade reads a list (a single band). The classes' own lists are left as the decision wrote them.
    pub(crate) fn join(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        g: u32,
        classes: &[(u32, u32)],
        height: u32,
    ) -> GeometryTiles {
        let words = self.params.section_words as u64;
        let base = g as u64 * words * 4;
        let total: u32 = classes.iter().map(|&(_, n)| n).sum();
        // Written before this submission's copies run; they leave the header alone.
        ctx.queue.write_buffer(
            &self.group_tiles,
            base,
            bytemuck::cast_slice(&[total, 1u32, 1, 0]),
        );
        let mut at = base + TILE_LIST_HEADER as u64 * 4;
        for &(c, n) in classes.iter().filter(|&&(_, n)| n > 0) {
            enc.copy_buffer_to_buffer(
                &self.class_tiles,
                c as u64 * words * 4 + TILE_LIST_HEADER as u64 * 4,
                &self.group_tiles,
                at,
                n as u64 * 4,
            );
            at += n as u64 * 4;
        }
        GeometryTiles::section(&self.group_tiles, base, words * 4, height)
    }

    /// Class `c`'s tile list as shade reads one (a single band).
    pub(crate) fn class_list(&self, c: u32, height: u32) -> GeometryTiles {
        let words = self.params.section_words as u64;
        GeometryTiles::section(&self.class_tiles, c as u64 * words * 4, words * 4, height)
    }
}
