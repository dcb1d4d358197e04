//! shadow_test: caches lit_k(p) of newly rendered maps as bits of each pixel's lattice mask; under
//! scope = local only for the (pixel, sample) pairs the level's items and probes consult, once each.

use super::shade::GeometryTiles;
use super::{ComputeKernel, Dispatch};
use crate::gpu::kernels::MapAccess;
use crate::gpu::stages::bind;
use crate::gpu::structs::{GpuLevel, GpuTestBlock};
use crate::gpu::{readback, GpuContext, Stage};
use crate::render::gbuffer::GBuffer;
use crate::stages::adaptive_buffers::{ItemLists, Masks, Requests, LATTICE_POINTS, MASK_WORDS};
use crate::Result;

/// Samples of a full block (`TEST_BLOCK` in kernels/shadow_test.wgsl, whose `block16` unrolls them).
pub const TEST_BLOCK: u32 = 16;
/// The entry points of the tails (the rest of a list, largest first), in slot order after the
/// full blocks; each unrolls exactly its size (llvmpipe would run the lines of a padded block too).
pub const TEST_TAILS: [u32; 4] = [8, 4, 2, 1];
/// Block slots: the full blocks of the longest list and the tails (`TEST_SLOTS` in the kernel).
pub const TEST_SLOTS: u32 = LATTICE_POINTS / TEST_BLOCK + TEST_TAILS.len() as u32;
pub const TEST_BLOCK_BYTES: u64 = std::mem::size_of::<GpuTestBlock>() as u64;
/// One slot's `dispatch_workgroups_indirect` arguments.
const ARGS_BYTES: u64 = 12;

/// The slots a list of at most `bound` samples can fill, with their block sizes: the host dispatches
/// each (indirectly; `fill_blocks` gives the unused ones no workgroups).
pub fn block_slots(bound: u32) -> Vec<(u32, u32)> {
    let full = bound / TEST_BLOCK;
    let mut slots: Vec<(u32, u32)> = (0..full).map(|s| (s, TEST_BLOCK)).collect();
    for (n, &size) in TEST_TAILS.iter().enumerate() {
        if size <= bound {
            slots.push((full + n as u32, size));
        }
    }
    slots
}

pub struct ShadowTest {
    /// scope = global: `fill_blocks`, then `block16`, `block8`, `block4`, `block2`, `block1`.
    fill: ComputeKernel,
    blocks: [ComputeKernel; 5],
    /// TEST_SLOTS blocks (uniform in the block dispatches, written by `fill_blocks`).
    pub block_buffer: wgpu::Buffer,
    /// Indirect arguments of each slot, written by `fill_blocks`.
    pub block_args: wgpu::Buffer,
    /// scope = local: `list` (items) and `probes`.
    local: Option<[ComputeKernel; 2]>,
}

impl ShadowTest {
    /// `maps`: how every entry point reads maps; `local`: also the entry points of scope = local.
    pub fn new(ctx: &GpuContext, maps: MapAccess, local: bool) -> Result<Self> {
        Self::build(
            ctx,
            maps,
            local,
            ["block16", "block8", "block4", "block2", "block1"],
        )
    }

    /// scope = global over a point light's cube maps: the blocks test each pixel on the face that
    /// holds its direction (`cube16` .. `cube1`).
    pub fn new_cube(ctx: &GpuContext, maps: MapAccess) -> Result<Self> {
        Self::build(
            ctx,
            maps,
            false,
            ["cube16", "cube8", "cube4", "cube2", "cube1"],
        )
    }

    fn build(ctx: &GpuContext, maps: MapAccess, local: bool, blocks: [&str; 5]) -> Result<Self> {
        let local = if local {
            Some([
                ComputeKernel::new_for(ctx, Stage::SHADOW_TEST, "list", maps)?,
                ComputeKernel::new_for(ctx, Stage::SHADOW_TEST, "probes", maps)?,
            ])
        } else {
            None
        };
        let block = |entry| ComputeKernel::new_for(ctx, Stage::SHADOW_TEST, entry, maps);
        let buffer = |label, size, usage| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: usage
                    | wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        Ok(Self {
            fill: ComputeKernel::new(ctx, Stage::SHADOW_TEST, "fill_blocks")?,
            blocks: [
                block(blocks[0])?,
                block(blocks[1])?,
                block(blocks[2])?,
                block(blocks[3])?,
                block(blocks[4])?,
            ],
            block_buffer: buffer(
                "shadow_test blocks",
                TEST_SLOTS as u64 * TEST_BLOCK_BYTES,
                wgpu::BufferUsages::UNIFORM,
            ),
            block_args: buffer(
                "shadow_test block args",
                TEST_SLOTS as u64 * ARGS_BYTES,
                wgpu::BufferUsages::INDIRECT,
            ),
            local,
        })
    }

    /// scope = local: tests the four corners of each of this level's items (`items.items[cur]`,
    /// counted by `items.total`) that no earlier item or probe of the frame tested for that pixel.
    pub(crate) fn record_list(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        t: &TestFrame,
        work: &LocalWork,
        cur: usize,
    ) {
        let kernels = self
            .local
            .as_ref()
            .expect("ShadowTest built for scope = local");
        let items = work.items;
        kernels[0].dispatch(
            ctx,
            enc,
            local_bindings(t, work, &items.items[cur], &items.total),
            Dispatch::Indirect(&items.list_args),
        );
    }

    /// scope = local: tests the five new samples of each of this level's probes (`items.probes`,
    /// counted by `items.probe_total`; `work.quads` holds the probed parents' children), once per pixel.
    pub(crate) fn record_probes(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        t: &TestFrame,
        work: &LocalWork,
    ) {
        let kernels = self
            .local
            .as_ref()
            .expect("ShadowTest built for scope = local");
        let items = work.items;
        kernels[1].dispatch(
            ctx,
            enc,
            local_bindings(t, work, &items.probes, &items.probe_total),
            Dispatch::Indirect(&items.probe_args),
        );
    }

    /// Tests lattice samples `ks` (ascending), whose maps are layers of `maps` (or slots of a
    /// hybrid store's view); skips those not requested this frame. The blocks run over the
    /// frame's geometry tiles (`t.tiles`).
    pub fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        t: &TestFrame,
        maps: &wgpu::TextureView,
        ks: &[u32],
    ) {
        let bound = ks.len() as u32;
        let level = readback::uniform_buffer(
            ctx,
            "level",
            &GpuLevel {
                work_count: bound,
                ..Default::default()
            },
        );
        let list = readback::storage_buffer(ctx, "test list", ks, wgpu::BufferUsages::empty());
        self.dispatch(
            ctx,
            enc,
            t,
            maps,
            SampleList {
                level: &level,
                list: &list,
                bound,
            },
        );
    }

    /// Tests the samples the last subdivide requested (`rq.decisions.new_samples`, as many as it
    /// appended, at most `bound`): the GPU-steered loop, when a level's maps fit one array.
    pub(crate) fn record_requested(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        t: &TestFrame,
        maps: &wgpu::TextureView,
        bound: u32,
    ) {
        let level = readback::uniform_buffer(
            ctx,
            "level",
            &GpuLevel {
                work_count: bound,
                requested: 1,
                ..Default::default()
            },
        );
        self.dispatch(
            ctx,
            enc,
            t,
            maps,
            SampleList {
                level: &level,
                list: &t.rq.decisions.new_samples,
                bound,
            },
        );
    }

    /// `fill_blocks`: the requested samples of `test_list` (see `level`) into the block slots
    /// (`blocks`: `block_buffer`), and each slot's dispatch arguments (`block_args`).
    pub fn record_fill(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        bindings: bind::shadow_test::FillBlocks,
    ) {
        self.fill
            .dispatch(ctx, enc, bindings, Dispatch::Direct([1, 1, 1]));
    }

    fn dispatch(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        t: &TestFrame,
        maps: &wgpu::TextureView,
        list: SampleList,
    ) {
        let (tiles, gbuffer, rq) = (t.tiles, t.gbuffer, t.rq);
        // A band at a time (`tiles.bands`): fill_blocks sizes each slot's dispatch by the band's
        // tiles, and the blocks write the band's rows of the masks.
        for band in &tiles.bands {
            let fill = bind::shadow_test::FillBlocks {
                level: list.level.as_entire_binding(),
                samples: rq.samples.as_entire_binding(),
                test_list: list.list.as_entire_binding(),
                lattice_state: rq.decisions.lattice_state.as_entire_binding(),
                control_words: rq.control.as_entire_binding(),
                blocks: self.block_buffer.as_entire_binding(),
                block_args: self.block_args.as_entire_binding(),
                tile_list: band.tiles(tiles),
            };
            self.record_fill(ctx, enc, fill);
            let masks = band.pixels(tiles, &t.out.lit, gbuffer.width, MASK_WORDS as u64 * 4);
            for (slot, size) in block_slots(list.bound) {
                let kernel = &self.blocks[(TEST_BLOCK / size).trailing_zeros() as usize];
                let block = wgpu::BufferBinding {
                    buffer: &self.block_buffer,
                    offset: slot as u64 * TEST_BLOCK_BYTES,
                    size: wgpu::BufferSize::new(TEST_BLOCK_BYTES),
                };
                kernel.dispatch(
                    ctx,
                    enc,
                    bind::shadow_test::Block {
                        frame: band.frame(t.frame).as_entire_binding(),
                        samples: rq.samples.as_entire_binding(),
                        gbuffer_position: wgpu::BindingResource::TextureView(
                            &gbuffer.position_view,
                        ),
                        gbuffer_normal: wgpu::BindingResource::TextureView(&gbuffer.normal_view),
                        shadow_maps: wgpu::BindingResource::TextureView(maps),
                        masks: masks.clone(),
                        block: wgpu::BindingResource::Buffer(block),
                        tile_list: band.tiles(tiles),
                    },
                    Dispatch::IndirectAt(&self.block_args, slot as u64 * ARGS_BYTES),
                );
            }
        }
    }
}

/// What every test of a frame reads and writes besides its samples' maps: the frame uniform, the
/// G-buffer and its geometry tiles, subdivide's requests with the sample records, and the masks.
#[derive(Clone, Copy)]
pub struct TestFrame<'b> {
    pub frame: &'b wgpu::Buffer,
    pub gbuffer: &'b GBuffer,
    pub tiles: &'b GeometryTiles,
    pub rq: Requests<'b>,
    pub out: &'b Masks,
}

/// scope = local, one level: its quads, its item lists and the two map arrays its samples' maps
/// are layers of.
#[derive(Clone, Copy)]
pub(crate) struct LocalWork<'b> {
    pub(crate) quads: &'b wgpu::Buffer,
    pub(crate) items: &'b ItemLists,
    pub(crate) maps: [&'b wgpu::TextureView; 2],
}

/// The samples one global test takes: `level` (its count, and whether it is subdivide's request
/// list) and the list, at most `bound` long.
#[derive(Clone, Copy)]
struct SampleList<'b> {
    level: &'b wgpu::Buffer,
    list: &'b wgpu::Buffer,
    bound: u32,
}

/// `list` and `probes`: the work list `work` (items or probes), counted by `total`.
fn local_bindings<'b>(
    t: &TestFrame<'b>,
    work: &LocalWork<'b>,
    list: &'b wgpu::Buffer,
    total: &'b wgpu::Buffer,
) -> bind::shadow_test::Local<'b> {
    bind::shadow_test::Local {
        frame: t.frame.as_entire_binding(),
        samples: t.rq.samples.as_entire_binding(),
        gbuffer_position: wgpu::BindingResource::TextureView(&t.gbuffer.position_view),
        gbuffer_normal: wgpu::BindingResource::TextureView(&t.gbuffer.normal_view),
        consulted: t.out.consulted.as_entire_binding(),
        lattice_lit: t.out.lit.as_entire_binding(),
        maps_a: wgpu::BindingResource::TextureView(work.maps[0]),
        maps_b: wgpu::BindingResource::TextureView(work.maps[1]),
        work: list.as_entire_binding(),
        work_total: total.as_entire_binding(),
        quads: work.quads.as_entire_binding(),
        control: t.rq.control.as_entire_binding(),
    }
}
