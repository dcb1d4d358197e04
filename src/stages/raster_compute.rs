//! raster_compute: depth-only shadow maps in compute kernels, many maps per dispatch chain, by
//! exact rules its CPU twin (`twin::raster_compute`) repeats bit for bit (docs/gpu-frame.md §7).
//! A chain clears its maps, sets up every (triangle, map) pair (a triangle per invocation over all
//! the chain's maps, so vertices are read once per chain), rasterizes the small ones at once and
//! queues the large ones (an entry per block of a pair's tiles), then rasterizes the queued ones
//! tile by tile. Depth is one u32 per
//! texel: the bits of a non-negative f32, which order like the values, written by atomicMin.

use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP};
use crate::gpu::readback;
use crate::gpu::stages::bind;
use crate::gpu::structs::{GpuRasterCompute, GpuRasterJob};
use crate::gpu::{GpuContext, Stage};
use crate::render::SceneGpu;
use crate::scene::CullMode;
use crate::{Error, Result};

/// The stored word of the far value (1.0), which every map is cleared to.
pub const FAR: u32 = 0x3f80_0000;
/// Large (triangle, map) pairs one chain can queue per map of the chain (at least this many, and
/// one per triangle of the mesh where it has more: a triangle is one pair per map), between a
/// least and a most; beyond it `main` rasterizes them itself, one invocation a pair, which a GPU
/// runs badly: `grove`'s leaves make 66–70 k large pairs per 512² map, and with a queue of 2^18
/// for its 289 maps a lattice frame took 10 s on an H100 against 147 ms with 2^24
/// (results/bench-seed-table2-h100-rasters/). Maps fitted to a window (`regions`) make most of a
/// mesh's triangles large: a per-map figure that ignores the mesh overflowed there.
pub(crate) const LARGE_PAIRS_PER_MAP: u64 = 1 << 16;
pub(crate) const LARGE_CAPACITY_MIN: u64 = 1 << 18;
pub(crate) const LARGE_CAPACITY_MAX: u64 = 1 << 24;
/// `requested`'s output words (the kernel's STEER_ARGS_*: the map count, then three dispatches).
pub(crate) const STEER_ARGS_WORDS: u64 = 10;
pub const STEER_ARGS_CLEAR: u64 = 1;
pub const STEER_ARGS_MAIN: u64 = 4;
pub const STEER_ARGS_STORE: u64 = 7;
/// Words each invocation of `clear` sets (the kernel's RASTER_CLEAR_RUN).
pub const CLEAR_RUN: u32 = 16;
/// Most maps in one chain: a queued entry names its map in 16 bits (the kernel's RASTER_MAP_BITS).
pub(crate) const MAX_CHAIN_MAPS: u64 = (1 << 16) - 1;
/// Workgroups along x of a 2D dispatch over many items (rows of at most this many).
const ROW: u32 = 32768;

pub struct RasterCompute {
    clear: ComputeKernel,
    main: ComputeKernel,
    main_maps: ComputeKernel,
    begin: ComputeKernel,
    large_tiles: ComputeKernel,
    requested: ComputeKernel,
    kept_extent: ComputeKernel,
    store: ComputeKernel,
    /// `capacity` maps of `map_size`² words.
    pub(crate) depth: wgpu::Buffer,
    large: wgpu::Buffer,
    /// Pairs `large` holds.
    pub(crate) large_capacity: u32,
    control: wgpu::Buffer,
    dispatch: wgpu::Buffer,
    /// `requested`'s output: the chain's map count, then the dispatches of clear, main and store.
    steer_args: wgpu::Buffer,
    pub(crate) map_size: u32,
    /// Maps one chain holds.
    pub capacity: u32,
    /// The mesh size the queue was sized for (0: the per-map floor alone).
    pub(crate) triangles: u32,
    cull_face: u32,
}

/// The requests one steered chain rasterizes: `control` (word 1 counts a level's requests),
/// `list` (the requested samples) and the first of them this chain takes.
#[derive(Clone, Copy)]
pub struct Requests<'b> {
    pub control: &'b wgpu::Buffer,
    pub list: &'b wgpu::Buffer,
    pub first: u32,
}

/// One chain's inputs: the scene, the samples whose view-projections the jobs name, and the chain's
/// uniform and jobs.
#[derive(Clone, Copy)]
struct Chain<'b> {
    scene: &'b SceneGpu,
    samples: &'b wgpu::Buffer,
    params: &'b wgpu::Buffer,
    jobs: &'b wgpu::Buffer,
}

/// Which `main` a chain runs: `main` over the cull pass's kept index lists and their draw
/// arguments (jobs with a kept_slot read them), or `main_maps` over the shadow order, reading the
/// level's request count when steered.
enum ChainMain<'b> {
    Kept {
        indices: &'b wgpu::Buffer,
        counts: &'b wgpu::Buffer,
        dispatch: Dispatch<'b>,
    },
    Maps {
        requests: Option<&'b wgpu::Buffer>,
        dispatch: Dispatch<'b>,
    },
}

/// Maps one chain may hold: the memory budget and the storage-binding limit, whichever is less.
pub fn maps_per_chain(ctx: &GpuContext, map_size: u32, budget_mib: u32) -> Result<u32> {
    let map_bytes = map_size as u64 * map_size as u64 * 4;
    let binding = ctx.limits().max_storage_buffer_binding_size;
    let by_budget = (budget_mib as u64 * 1024 * 1024) / map_bytes;
    if by_budget == 0 {
        return Err(Error::Limit(format!(
            "one {map_size}x{map_size} shadow map ({} MiB) does not fit shadow_map_budget_mib = {budget_mib}",
            map_bytes.div_ceil(1024 * 1024)
        )));
    }
    let by_binding = binding / map_bytes;
    if by_binding == 0 {
        return Err(Error::Limit(format!(
            "shadow_map_size {map_size}: one map ({map_bytes} bytes) exceeds this device's storage binding limit of {binding} bytes ({})",
            ctx.summary.name
        )));
    }
    let rows = ctx.limits().max_compute_workgroups_per_dimension as u64;
    Ok(by_budget.min(by_binding).min(rows).min(MAX_CHAIN_MAPS) as u32)
}

/// The large-pair queue's size for a chain of `maps` maps: LARGE_PAIRS_PER_MAP each, within
/// [LARGE_CAPACITY_MIN, LARGE_CAPACITY_MAX] and one storage binding (`binding` bytes, 8 a pair).
pub fn large_capacity(maps: u32, binding: u64) -> u32 {
    large_capacity_for(maps, 0, binding)
}

/// The queue for a chain of `maps` maps over a mesh of `triangles`: per map the larger of
/// LARGE_PAIRS_PER_MAP and the triangle count, within the least, the most and one binding.
pub fn large_capacity_for(maps: u32, triangles: u32, binding: u64) -> u32 {
    (maps as u64 * LARGE_PAIRS_PER_MAP.max(triangles as u64))
        .clamp(LARGE_CAPACITY_MIN, LARGE_CAPACITY_MAX)
        .min(binding / 8) as u32
}

impl RasterCompute {
    /// A chain of at most `maps` maps (fewer where `shadow_map_budget_mib` or the device allows fewer).
    pub fn new(
        ctx: &GpuContext,
        map_size: u32,
        cull: CullMode,
        maps: u32,
        budget_mib: u32,
    ) -> Result<Self> {
        Self::with_queue(ctx, map_size, cull, maps, budget_mib, None)
    }

    /// As `new`, with the queue sized for a mesh of `triangles` (large_capacity_for).
    pub(crate) fn for_mesh(
        ctx: &GpuContext,
        map_size: u32,
        cull: CullMode,
        maps: u32,
        budget_mib: u32,
        triangles: u32,
    ) -> Result<Self> {
        let capacity = maps_per_chain(ctx, map_size, budget_mib)?.min(maps.max(1));
        let pairs = large_capacity_for(
            capacity,
            triangles,
            ctx.limits().max_storage_buffer_binding_size,
        );
        Ok(Self {
            triangles,
            ..Self::with_queue(ctx, map_size, cull, maps, budget_mib, Some(pairs))?
        })
    }

    /// As `new`, with a large-pair queue of `pairs` instead of `large_capacity`'s (a test drives
    /// the path past a full queue with it).
    pub fn with_queue(
        ctx: &GpuContext,
        map_size: u32,
        cull: CullMode,
        maps: u32,
        budget_mib: u32,
        pairs: Option<u32>,
    ) -> Result<Self> {
        let capacity = maps_per_chain(ctx, map_size, budget_mib)?.min(maps.max(1));
        let large_capacity = pairs
            .unwrap_or_else(|| {
                large_capacity(capacity, ctx.limits().max_storage_buffer_binding_size)
            })
            .max(1);
        let storage =
            |label, bytes: u64, extra| readback::zeroed_storage_with(ctx, label, bytes, extra);
        Ok(Self {
            clear: ComputeKernel::new(ctx, Stage::RASTER_COMPUTE, "clear")?,
            main: ComputeKernel::new(ctx, Stage::RASTER_COMPUTE, "main")?,
            main_maps: ComputeKernel::new(ctx, Stage::RASTER_COMPUTE, "main_maps")?,
            begin: ComputeKernel::new(ctx, Stage::RASTER_COMPUTE, "begin")?,
            large_tiles: ComputeKernel::new(ctx, Stage::RASTER_COMPUTE, "large_tiles")?,
            requested: ComputeKernel::new(ctx, Stage::RASTER_COMPUTE, "requested")?,
            kept_extent: ComputeKernel::new(ctx, Stage::RASTER_COMPUTE, "kept_extent")?,
            store: ComputeKernel::new(ctx, Stage::RASTER_COMPUTE, "store")?,
            depth: storage(
                "raster_compute depth",
                capacity as u64 * map_size as u64 * map_size as u64 * 4,
                wgpu::BufferUsages::empty(),
            ),
            large: storage(
                "raster_compute large pairs",
                large_capacity as u64 * 8,
                wgpu::BufferUsages::empty(),
            ),
            large_capacity,
            control: storage("raster_compute control", 16, wgpu::BufferUsages::empty()),
            dispatch: storage("raster_compute dispatch", 16, wgpu::BufferUsages::INDIRECT),
            steer_args: storage(
                "raster_compute steered dispatches",
                STEER_ARGS_WORDS * 4,
                wgpu::BufferUsages::INDIRECT,
            ),
            map_size,
            capacity,
            triangles: 0,
            cull_face: super::cull::cull_face(cull),
        })
    }

    fn uniform(
        &self,
        ctx: &GpuContext,
        scene: &SceneGpu,
        maps: u32,
        first_request: u32,
        steered: bool,
    ) -> wgpu::Buffer {
        let uniform = GpuRasterCompute {
            map_size: self.map_size,
            triangle_count: scene.index_count / 3,
            cull_face: self.cull_face,
            map_count: maps,
            large_capacity: self.large_capacity,
            fence: 0,
            first_request,
            steered: u32::from(steered),
        };
        readback::uniform_buffer(ctx, "raster_compute", &uniform)
    }

    /// Rasterizes `scene` into maps 0..jobs.len() of `depth`, map m from sample `jobs[m].sample` of
    /// `samples` (the hardware raster's `GpuSample`s: the same view-projections) inside its rectangle.
    pub fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &SceneGpu,
        samples: &wgpu::Buffer,
        jobs: &[GpuRasterJob],
    ) {
        self.record_kept(ctx, enc, scene, samples, jobs, None)
    }

    /// [`record`](Self::record) where jobs with a `kept_slot` draw the cull pass's kept triangles
    /// of that slot: `kept` is the pass's (kept index lists, draw arguments).
    pub fn record_kept(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &SceneGpu,
        samples: &wgpu::Buffer,
        jobs: &[GpuRasterJob],
        kept: Option<(&wgpu::Buffer, &wgpu::Buffer)>,
    ) {
        let maps = jobs.len() as u32;
        assert!(
            maps >= 1 && maps <= self.capacity,
            "raster_compute chain of {maps} maps, capacity {}",
            self.capacity
        );
        let params = self.uniform(ctx, scene, maps, 0, false);
        let jobs = readback::storage_buffer(
            ctx,
            "raster_compute jobs",
            jobs,
            wgpu::BufferUsages::empty(),
        );
        let words = groups(
            maps * self.map_size * self.map_size,
            LINE_WORKGROUP[0] * CLEAR_RUN,
        );
        let [x, _, z] = rows(groups(scene.index_count / 3, LINE_WORKGROUP[0]));
        let chain = Chain {
            scene,
            samples,
            params: &params,
            jobs: &jobs,
        };
        let main = match kept {
            // A triangle per invocation over every map: its vertices are read once per chain.
            None => ChainMain::Maps {
                requests: None,
                dispatch: Dispatch::Direct([x, 1, z]),
            },
            Some((indices, counts)) => {
                // As wide as the longest kept list: lavapipe pays for every workgroup, even one that returns at once.
                self.kept_extent.dispatch(
                    ctx,
                    enc,
                    bind::raster_compute::KeptExtent {
                        params: params.as_entire_binding(),
                        jobs: jobs.as_entire_binding(),
                        steer_args: self.steer_args.as_entire_binding(),
                        kept_counts: counts.as_entire_binding(),
                    },
                    Dispatch::Direct([1, 1, 1]),
                );
                ChainMain::Kept {
                    indices,
                    counts,
                    dispatch: Dispatch::IndirectAt(&self.steer_args, STEER_ARGS_MAIN * 4),
                }
            }
        };
        self.record_chain(ctx, enc, &chain, Dispatch::Direct(rows(words)), main);
    }

    /// clear, main, begin and large_tiles over the chain's jobs, with clear's and main's dispatches.
    fn record_chain(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        chain: &Chain,
        clear: Dispatch,
        main: ChainMain,
    ) {
        use bind::raster_compute::{Begin, Clear, LargeTiles, Main, MainMaps};
        let Chain {
            scene,
            samples,
            params,
            jobs,
        } = *chain;
        enc.clear_buffer(&self.control, 0, None);
        self.clear.dispatch(
            ctx,
            enc,
            Clear {
                params: params.as_entire_binding(),
                depth: self.depth.as_entire_binding(),
            },
            clear,
        );
        let indices = match main {
            ChainMain::Kept {
                indices,
                counts,
                dispatch,
            } => {
                let bindings = Main {
                    params: params.as_entire_binding(),
                    samples: samples.as_entire_binding(),
                    jobs: jobs.as_entire_binding(),
                    positions: scene.positions.as_entire_binding(),
                    indices: indices.as_entire_binding(),
                    depth: self.depth.as_entire_binding(),
                    large: self.large.as_entire_binding(),
                    control: self.control.as_entire_binding(),
                    runs: scene.runs.as_entire_binding(),
                    kept_counts: counts.as_entire_binding(),
                };
                self.main.dispatch(ctx, enc, bindings, dispatch);
                indices
            }
            ChainMain::Maps { requests, dispatch } => {
                let bindings = MainMaps {
                    params: params.as_entire_binding(),
                    samples: samples.as_entire_binding(),
                    jobs: jobs.as_entire_binding(),
                    positions: scene.positions.as_entire_binding(),
                    indices: scene.shadow_indices.as_entire_binding(),
                    depth: self.depth.as_entire_binding(),
                    large: self.large.as_entire_binding(),
                    control: self.control.as_entire_binding(),
                    // Read only when steered; otherwise any read-only buffer fills the binding.
                    request_control: requests.unwrap_or(samples).as_entire_binding(),
                    runs: scene.runs.as_entire_binding(),
                };
                self.main_maps.dispatch(ctx, enc, bindings, dispatch);
                &scene.shadow_indices
            }
        };
        let begin = Begin {
            params: params.as_entire_binding(),
            control: self.control.as_entire_binding(),
            dispatch: self.dispatch.as_entire_binding(),
        };
        self.begin
            .dispatch(ctx, enc, begin, Dispatch::Direct([1, 1, 1]));
        let large = LargeTiles {
            params: params.as_entire_binding(),
            samples: samples.as_entire_binding(),
            jobs: jobs.as_entire_binding(),
            positions: scene.positions.as_entire_binding(),
            indices: indices.as_entire_binding(),
            depth: self.depth.as_entire_binding(),
            large: self.large.as_entire_binding(),
            control: self.control.as_entire_binding(),
        };
        self.large_tiles
            .dispatch(ctx, enc, large, Dispatch::Indirect(&self.dispatch));
    }

    /// Under the GPU-steered loop: rasterizes the requests `requests.first ..` (at most `capacity`)
    /// of a level's list (`requests.control` word 1 counts them, `requests.list` names the samples)
    /// and stores each map into the layer its sample record names, with dispatches the GPU sizes:
    /// a chain past the last request does nothing. Nothing is read back.
    pub fn record_requested(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &SceneGpu,
        samples: &wgpu::Buffer,
        requests: &Requests,
        layers: &wgpu::TextureView,
    ) {
        let (requests, first_request) = ((requests.control, requests.list), requests.first);
        let params = self.uniform(ctx, scene, self.capacity, first_request, true);
        let jobs = readback::zeroed_storage(
            ctx,
            "raster_compute requested jobs",
            self.capacity as u64 * std::mem::size_of::<GpuRasterJob>() as u64,
        );
        self.requested.dispatch(
            ctx,
            enc,
            bind::raster_compute::Requested {
                params: params.as_entire_binding(),
                jobs: jobs.as_entire_binding(),
                request_control: requests.0.as_entire_binding(),
                request_list: requests.1.as_entire_binding(),
                steer_args: self.steer_args.as_entire_binding(),
            },
            Dispatch::Direct([1, 1, 1]),
        );
        let at = |words: u64| Dispatch::IndirectAt(&self.steer_args, words * 4);
        let chain = Chain {
            scene,
            samples,
            params: &params,
            jobs: &jobs,
        };
        self.record_chain(
            ctx,
            enc,
            &chain,
            at(STEER_ARGS_CLEAR),
            ChainMain::Maps {
                requests: Some(requests.0),
                dispatch: at(STEER_ARGS_MAIN),
            },
        );
        self.store.dispatch(
            ctx,
            enc,
            bind::raster_compute::Store {
                params: params.as_entire_binding(),
                jobs: jobs.as_entire_binding(),
                depth: self.depth.as_entire_binding(),
                layers: wgpu::BindingResource::TextureView(layers),
                layer_samples: samples.as_entire_binding(),
            },
            at(STEER_ARGS_STORE),
        );
    }

    /// `requested`'s output of the last chain: [maps, clear x y z, main x y z, store x y z] (a read-back).
    pub fn read_steer_args(&self, ctx: &GpuContext) -> Result<Vec<u32>> {
        readback::read_buffer(ctx, &self.steer_args, STEER_ARGS_WORDS * 4)
    }

    /// Copies map `m` of the chain into layer `layer` of an R32Uint array of the same size (after
    /// `record`, in the same encoder). Rows go in one copy where their bytes meet the copy
    /// alignment (map sizes that are multiples of 64), else one copy per row.
    pub(crate) fn copy_map(
        &self,
        enc: &mut wgpu::CommandEncoder,
        m: u32,
        texture: &wgpu::Texture,
        layer: u32,
    ) {
        self.copy_rect(enc, m, texture, layer, [0, 0, self.map_size, self.map_size]);
    }

    /// `copy_map` of the texels `[x, y, w, h]` alone: a kept map's rectangle drawn again, the
    /// rest of the layer kept (docs/reuse.md).
    pub(crate) fn copy_rect(
        &self,
        enc: &mut wgpu::CommandEncoder,
        m: u32,
        texture: &wgpu::Texture,
        layer: u32,
        [x, y, w, h]: [u32; 4],
    ) {
        let size = self.map_size;
        let row = size * 4;
        let map_at = m as u64 * size as u64 * row as u64;
        let whole = row % wgpu::COPY_BYTES_PER_ROW_ALIGNMENT == 0;
        let (copies, rows) = if whole { (1, h) } else { (h, 1) };
        for r in 0..copies {
            let at = map_at + ((y + r) as u64 * size as u64 + x as u64) * 4;
            enc.copy_buffer_to_texture(
                wgpu::TexelCopyBufferInfo {
                    buffer: &self.depth,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: at,
                        bytes_per_row: whole.then_some(row),
                        rows_per_image: whole.then_some(rows),
                    },
                },
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d {
                        x,
                        y: y + r,
                        z: layer,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::Extent3d {
                    width: w,
                    height: rows,
                    depth_or_array_layers: 1,
                },
            );
        }
    }

    /// The stored words of maps 0..maps, as the kernel wrote them.
    pub fn read_words(&self, ctx: &GpuContext, maps: u32) -> Result<Vec<u32>> {
        assert!(maps <= self.capacity);
        readback::read_buffer(
            ctx,
            &self.depth,
            maps as u64 * self.map_size as u64 * self.map_size as u64 * 4,
        )
    }
}

/// Texel by texel, one compute map (`words`) against the fixed-function raster's map of the same
/// sample (`fixed`, depths): where one covers and the other does not, and where both cover but the
/// depths differ, in linear depth, by more than a tenth or a hundredth of a texel's width at that
/// depth (docs/gpu-frame.md §7; the lookup's constant bias is half a texel).
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct RasterDifference {
    pub texels: usize,
    pub covered: usize,
    pub(crate) exact: usize,
    pub coverage: usize,
    pub tenth: usize,
    pub(crate) hundredth: usize,
}

impl RasterDifference {
    pub fn add(&mut self, s: &crate::gpu::structs::GpuSample, fixed: &[f32], words: &[u32]) {
        // Linear depth as shadow_lookup takes it: perspective, or an orthographic map's range.
        let linear = |d: f32| {
            if s.orthographic != 0 {
                s.depth_lin_a * d + s.depth_lin_b
            } else {
                s.depth_lin_a / (d + s.depth_lin_b)
            }
        };
        self.texels += fixed.len();
        for (&h, &w) in fixed.iter().zip(words) {
            let c = depth_of(w);
            match (h < 1.0, c < 1.0) {
                (true, true) => {
                    self.covered += 1;
                    self.exact += usize::from(h == c);
                    let texels = (linear(h) - linear(c)).abs() / (linear(h) * s.texel_angle);
                    self.tenth += usize::from(texels > 0.1);
                    self.hundredth += usize::from(texels > 0.01);
                }
                (false, false) => {}
                _ => self.coverage += 1,
            }
        }
    }
    /// A count as a share of all texels.
    pub fn share(&self, n: usize) -> f64 {
        n as f64 / self.texels.max(1) as f64
    }
    /// One line: each count and its share.
    pub fn summary(&self) -> String {
        let pc = |n: usize| format!("{n} ({:.5}%)", 100.0 * self.share(n));
        format!(
            "{} texels, covered by both {} ({} equal); coverage differs at {}; depth by > 0.1 texel at {}, by > 0.01 at {}",
            self.texels,
            self.covered,
            self.exact,
            pc(self.coverage),
            pc(self.tenth),
            pc(self.hundredth)
        )
    }
}

/// A stored word's depth.
pub(crate) fn depth_of(word: u32) -> f32 {
    f32::from_bits(word)
}

/// `n` workgroups as (x, 1, z) with x at most ROW: the kernels index them as z · x + x.
fn rows(n: u32) -> [u32; 3] {
    let x = n.clamp(1, ROW);
    [x, 1, n.div_ceil(x)]
}
