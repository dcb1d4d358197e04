//! reproject_count: c_q(p) for every (pixel, active quad) from the cached masks (dense), or for the
//! compacted (pixel, quad) items from the corners' bits shadow_test `list` cached (scope = local).

use super::shade::GeometryTiles;
use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::stages::adaptive_buffers::{CountMaps, ItemLists, Level, Masks, MASK_WORDS};
use crate::Result;

pub struct ReprojectCount {
    dense: ComputeKernel,
    list: ComputeKernel,
    last: ComputeKernel,
    begin: ComputeKernel,
}

impl ReprojectCount {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            dense: ComputeKernel::new(ctx, Stage::REPROJECT_COUNT, "main")?,
            list: ComputeKernel::new(ctx, Stage::REPROJECT_COUNT, "list")?,
            last: ComputeKernel::new(ctx, Stage::REPROJECT_COUNT, "last")?,
            begin: ComputeKernel::new(ctx, Stage::REPROJECT_COUNT, "begin")?,
        })
    }

    /// Every (pixel, quad) of `lv` from `masks.lit` into `out`; `control` counts geometry pixels.
    pub fn record_dense(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        lv: &Level,
        masks: &Masks,
        out: &CountMaps,
    ) {
        let words = lv.shape.height * lv.shape.words_per_row;
        self.dense.dispatch(
            ctx,
            enc,
            dense_bindings(lv, lv.frame, masks.lit.as_entire_binding(), out),
            Dispatch::Direct([groups(words, LINE_WORKGROUP[0]), 1, 1]),
        );
    }

    /// [`Self::record_dense`] a band of rows at a time (`tiles.bands`), the masks bound by band.
    pub(crate) fn record_dense_bands(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        lv: &Level,
        tiles: &GeometryTiles,
        masks: &Masks,
        out: &CountMaps,
    ) {
        let mask_bytes = MASK_WORDS as u64 * 4;
        for band in &tiles.bands {
            let lit = band.pixels(tiles, &masks.lit, lv.shape.width, mask_bytes);
            let words = band.rows * lv.shape.words_per_row;
            self.dense.dispatch(
                ctx,
                enc,
                dense_bindings(lv, band.frame(lv.frame), lit, out),
                Dispatch::Direct([groups(words, LINE_WORKGROUP[0]), 1, 1]),
            );
        }
    }

    /// scope = local: the items appended so far become this level's list (`items.total`,
    /// `items.list_args`), read by list, neighbourhood and compact.
    pub fn record_begin(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        level: &wgpu::Buffer,
        control: &wgpu::Buffer,
        items: &ItemLists,
    ) {
        self.begin.dispatch(
            ctx,
            enc,
            bind::reproject_count::Begin {
                level: level.as_entire_binding(),
                item_total: items.total.as_entire_binding(),
                control: control.as_entire_binding(),
                list_args: items.list_args.as_entire_binding(),
            },
            Dispatch::Direct([1, 1, 1]),
        );
    }

    /// scope = local: the counts of `items.items[lv.cur]` into `out`.
    pub(crate) fn record_list(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        lv: &Level,
        masks: &Masks,
        items: &ItemLists,
        out: &CountMaps,
    ) {
        let cur = lv.cur;
        self.list.dispatch(
            ctx,
            enc,
            bind::reproject_count::List {
                frame: lv.frame.as_entire_binding(),
                level: lv.uniform.as_entire_binding(),
                quads: lv.quads.as_entire_binding(),
                masks: masks.lit.as_entire_binding(),
                items: items.items[cur].as_entire_binding(),
                counts_atomic: out.maps.as_entire_binding(),
                item_total: items.total.as_entire_binding(),
            },
            Dispatch::Indirect(&items.list_args),
        );
    }

    /// The last level's items (scope = local): counts go straight into V's integer sums
    /// (`items.visibility_fixed`).
    pub(crate) fn record_last(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        lv: &Level,
        masks: &Masks,
        items: &ItemLists,
    ) {
        let cur = lv.cur;
        self.last.dispatch(
            ctx,
            enc,
            bind::reproject_count::Last {
                level: lv.uniform.as_entire_binding(),
                quads: lv.quads.as_entire_binding(),
                masks: masks.lit.as_entire_binding(),
                items: items.items[cur].as_entire_binding(),
                visibility_fixed: items.visibility_fixed.as_entire_binding(),
                item_total: items.total.as_entire_binding(),
            },
            Dispatch::Indirect(&items.list_args),
        );
    }
}

/// `main`'s bindings over `lv`, with the frame uniform and the masks of one band (or the whole frame).
fn dense_bindings<'b>(
    lv: &Level<'b>,
    frame: &'b wgpu::Buffer,
    lit: wgpu::BindingResource<'b>,
    out: &'b CountMaps,
) -> bind::reproject_count::Main<'b> {
    bind::reproject_count::Main {
        frame: frame.as_entire_binding(),
        level: lv.uniform.as_entire_binding(),
        quads: lv.quads.as_entire_binding(),
        masks: lit,
        counts: out.maps.as_entire_binding(),
        control: lv.control.as_entire_binding(),
        word_state: out.word_state.as_entire_binding(),
    }
}
