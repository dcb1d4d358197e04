//! compact (scope = local): next level's items, the uniform shares of unrefined quads, scissor
//! rectangles; `seed` and `resolve` start the item list and finish V (reproject_count `begin`
//! starts each level's list).

use super::shade::Screen;
use super::{groups, ComputeKernel, Dispatch, PIXEL_WORKGROUP};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::render::gbuffer::GBuffer;
use crate::stages::adaptive_buffers::{CountMaps, Decisions, Footprints, ItemLists, Level};
use crate::Result;

pub struct Compact {
    main: ComputeKernel,
    /// `main` that also grows the scissor rectangles and culling tiles (scissor or cull on).
    main_rects: ComputeKernel,
    seed: ComputeKernel,
    resolve: ComputeKernel,
}

/// What `main` reads and writes besides the level and the G-buffer: the counts, subdivide's
/// decisions, the next level's quads, the sample records, the item lists and the footprints.
#[derive(Clone, Copy)]
pub struct CompactInputs<'b> {
    pub counts: &'b CountMaps,
    pub decisions: &'b Decisions,
    pub next_quads: &'b wgpu::Buffer,
    pub samples: &'b wgpu::Buffer,
    pub items: &'b ItemLists,
    pub footprints: &'b Footprints,
}

impl Compact {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        let k = |e| ComputeKernel::new(ctx, Stage::COMPACT, e);
        Ok(Self {
            main: k("main")?,
            main_rects: k("main_rects")?,
            seed: k("seed")?,
            resolve: k("resolve")?,
        })
    }

    fn pixels(g: &GBuffer) -> Dispatch<'static> {
        Dispatch::Direct([
            groups(g.width, PIXEL_WORKGROUP[0]),
            groups(g.height, PIXEL_WORKGROUP[1]),
            1,
        ])
    }

    /// Every geometry pixel of `g` becomes an item of the root (`items.items[0]`), counted in `control`.
    pub(crate) fn record_seed(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        screen: &Screen,
        level: &wgpu::Buffer,
        control: &wgpu::Buffer,
        items: &ItemLists,
    ) {
        let (frame, g) = (screen.frame, screen.gbuffer);
        self.seed.dispatch(
            ctx,
            enc,
            bind::compact::Seed {
                frame: frame.as_entire_binding(),
                level: level.as_entire_binding(),
                next_items: items.items[0].as_entire_binding(),
                control: control.as_entire_binding(),
                gbuffer_position: wgpu::BindingResource::TextureView(&g.position_view),
            },
            Self::pixels(g),
        );
    }

    /// From this level's items (`items.items[lv.cur]`, their counts and the split decisions): the
    /// next level's items and quads' probes, the uniform shares of unrefined quads, and (`grow_rects`)
    /// the footprints of the next maps.
    pub fn record_main(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        lv: &Level,
        g: &GBuffer,
        inputs: &CompactInputs,
        grow_rects: bool,
    ) {
        let CompactInputs {
            counts,
            decisions,
            next_quads,
            samples,
            items,
            footprints,
        } = *inputs;
        let (control, cur) = (lv.control, lv.cur);
        // Both entry points share the item code, so both take every binding.
        let kernel = if grow_rects {
            &self.main_rects
        } else {
            &self.main
        };
        kernel.dispatch(
            ctx,
            enc,
            bind::compact::Main {
                frame: lv.frame.as_entire_binding(),
                level: lv.uniform.as_entire_binding(),
                items: items.items[cur].as_entire_binding(),
                counts: counts.maps.as_entire_binding(),
                split_base: decisions.split_base.as_entire_binding(),
                next_items: items.items[1 - cur].as_entire_binding(),
                control: control.as_entire_binding(),
                visibility_fixed: items.visibility_fixed.as_entire_binding(),
                next_quads: next_quads.as_entire_binding(),
                samples: samples.as_entire_binding(),
                rects: footprints.rects.as_entire_binding(),
                gbuffer_position: wgpu::BindingResource::TextureView(&g.position_view),
                gbuffer_normal: wgpu::BindingResource::TextureView(&g.normal_view),
                item_total: items.total.as_entire_binding(),
                probes: items.probes.as_entire_binding(),
                tiles: footprints.tiles.as_entire_binding(),
            },
            Dispatch::Indirect(&items.list_args),
        );
    }

    /// V from the integer sums (`items.visibility_fixed`) into the screen's V.
    pub(crate) fn record_resolve(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        screen: &Screen,
        level: &wgpu::Buffer,
        items: &ItemLists,
    ) {
        let (frame, g, visibility) = (screen.frame, screen.gbuffer, screen.visibility);
        self.resolve.dispatch(
            ctx,
            enc,
            bind::compact::Resolve {
                frame: frame.as_entire_binding(),
                level: level.as_entire_binding(),
                visibility_fixed: items.visibility_fixed.as_entire_binding(),
                visibility: visibility.as_entire_binding(),
            },
            Self::pixels(g),
        );
    }
}
