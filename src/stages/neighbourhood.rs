//! neighbourhood: the uniform-3x3 low-quality test, one flag bit per (pixel, quad).

use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP};
use crate::gpu::stages::bind;
use crate::gpu::{GpuContext, Stage};
use crate::stages::adaptive_buffers::{CountMaps, ItemLists, Level, LowQuality};
use crate::Result;

pub struct Neighbourhood {
    dense: ComputeKernel,
    list: ComputeKernel,
}

impl Neighbourhood {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(Self {
            dense: ComputeKernel::new(ctx, Stage::NEIGHBOURHOOD, "main")?,
            list: ComputeKernel::new(ctx, Stage::NEIGHBOURHOOD, "list")?,
        })
    }

    /// One pass over the flag words (writes `out.flags`); the level uniform's quad count (a GPU
    /// copy in the steered loop) bounds the quads each thread tests.
    pub fn record_dense(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        lv: &Level,
        counts: &CountMaps,
        out: &LowQuality,
    ) {
        let words = lv.shape.height * lv.shape.flag_words_per_row;
        self.dense.dispatch(
            ctx,
            enc,
            bind::neighbourhood::Main {
                frame: lv.frame.as_entire_binding(),
                level: lv.uniform.as_entire_binding(),
                counts: counts.maps.as_entire_binding(),
                flags: out.flags.as_entire_binding(),
                word_state: counts.word_state.as_entire_binding(),
            },
            Dispatch::Direct([groups(words, LINE_WORKGROUP[0]), 1, 1]),
        );
    }

    /// scope = local: one item of `items.items[cur]` each; also counts each quad's low-quality
    /// pixels (`out.per_quad`, which the level cleared), so no quad_count pass follows.
    pub(crate) fn record_list(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        lv: &Level,
        counts: &CountMaps,
        items: &ItemLists,
        out: &LowQuality,
    ) {
        let cur = lv.cur;
        self.list.dispatch(
            ctx,
            enc,
            bind::neighbourhood::List {
                frame: lv.frame.as_entire_binding(),
                level: lv.uniform.as_entire_binding(),
                counts: counts.maps.as_entire_binding(),
                items: items.items[cur].as_entire_binding(),
                flags_atomic: out.flags.as_entire_binding(),
                item_total: items.total.as_entire_binding(),
                word_state: counts.word_state.as_entire_binding(),
                quad_counters: out.per_quad.as_entire_binding(),
            },
            Dispatch::Indirect(&items.list_args),
        );
    }
}
