//! The stage table: every stage of a frame, once. A stage's name is its WGSL file, its pass and
//! twin modules, its debug label, its timing key and its key in `run.json`'s `stages_ms`; the
//! table also gives its kernel, its entry points (workgroup size and bindings, by the WGSL
//! variable's name) and its part of the frame split. The kernel registry (`gpu::kernels`), the
//! timer (`gpu::timing`), the passes (each binds its entry point's generated struct,
//! `bind::<stage>::<Set>`, through `stages::ComputeKernel`) and the naga tests (tests/kernels.rs)
//! all read it, so adding a stage is its kernel file, its pass and one entry here (and its CPU
//! twin); docs/adding-a-stage.md walks through it.

/// 2D pixel kernels.
pub(crate) const PIXEL_WORKGROUP: [u32; 3] = [8, 8, 1];
/// 1D kernels over words, items or quads.
pub(crate) const LINE_WORKGROUP: [u32; 3] = [64, 1, 1];
/// One invocation: kernels that write a few counters or dispatch arguments.
pub(crate) const SINGLE_WORKGROUP: [u32; 3] = [1, 1, 1];
/// Consecutive triangles whose box `cull` tests first (`CULL_RUN` in kernels/cull.wgsl): the
/// workgroup of its `triangles` entry point.
pub const CULL_RUN: u32 = 32;

/// The parts a frame's time splits into (docs/gpu-frame.md §3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Split {
    /// The G-buffer, the shadow maps and what prepares them (cull, moments, blur, hybrid build).
    Raster,
    /// Deciding where to sample: the adaptive counting, subdivision, compaction, probe, weights and
    /// the per-level read-back the loop needs (and the environment method's own).
    Decision,
    /// Every lookup of a map or ray that makes V: shadow_test, shade, the filters, the tracer.
    Shade,
    /// Read-backs of results: V and the pictures.
    Waits,
}

impl Split {
    pub const ALL: [Split; 4] = [Split::Raster, Split::Decision, Split::Shade, Split::Waits];

    pub fn name(self) -> &'static str {
        match self {
            Split::Raster => "raster",
            Split::Decision => "decision",
            Split::Shade => "shade",
            Split::Waits => "waits",
        }
    }
}

/// A WGSL file and what it is built with (plain concatenation, see `gpu::kernels`).
#[derive(Clone, Copy, Debug)]
pub struct Kernel {
    pub body: &'static str,
    /// Reads shadow maps through `map_depth`: built for every map access form (`MapAccess::forms`).
    pub reads_maps: bool,
    /// Reads the raster's own layers through `layer_depth` (moments, hybrid_build): built for the
    /// depth and words forms.
    pub reads_raster: bool,
    /// Needs the environment prelude (its structs and the BVH ray test).
    pub environment: bool,
    /// Needs the PCF family's tap patterns.
    pub pcf_taps: bool,
}

impl Kernel {
    pub const fn plain(body: &'static str) -> Self {
        Self {
            body,
            reads_maps: false,
            reads_raster: false,
            environment: false,
            pcf_taps: false,
        }
    }
}

/// One entry point: its workgroup size (`None` for a render pipeline's vertex or fragment entry)
/// and every binding it uses, as (WGSL variable, @binding) of group 0. tests/kernels.rs checks
/// both against what naga reads from the kernel.
#[derive(Clone, Copy, Debug)]
pub struct Entry {
    pub name: &'static str,
    pub workgroup: Option<[u32; 3]>,
    pub bindings: &'static [(&'static str, u32)],
}

const fn compute(
    name: &'static str,
    workgroup: [u32; 3],
    bindings: &'static [(&'static str, u32)],
) -> Entry {
    Entry {
        name,
        workgroup: Some(workgroup),
        bindings,
    }
}

const fn render(name: &'static str, bindings: &'static [(&'static str, u32)]) -> Entry {
    Entry {
        name,
        workgroup: None,
        bindings,
    }
}

/// A stage: a kernel's passes, or host work with a timing key of its own (read-backs, copies, CPU
/// work). Compared by name.
#[derive(Clone, Copy, Debug)]
pub struct Stage {
    pub name: &'static str,
    pub kernel: Option<Kernel>,
    pub entries: &'static [Entry],
    /// Its part of the frame split; `None` for work outside the frame (setup, pipeline build, upload).
    pub split: Option<Split>,
}

impl PartialEq for Stage {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}
impl Eq for Stage {}

impl std::fmt::Display for Stage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name)
    }
}

impl Stage {
    /// The stage named `name` (a kernel, or a `stages_ms` key).
    pub fn named(name: &str) -> Option<Stage> {
        STAGES.iter().find(|s| s.name == name).copied()
    }

    /// The entry point `name` of this stage's kernel.
    pub fn entry(&self, name: &str) -> Option<&'static Entry> {
        self.entries.iter().find(|e| e.name == name)
    }
}

/// A compute entry point's bindings as one value: a struct with a field per WGSL variable the
/// entry point uses, generated from the stage table (`bind::<stage>::<Set>`), so a pass that leaves
/// one out or misspells one does not compile. A kernel takes the set of its entry point.
///
/// ```
/// use penumbra::research::gpu::stages::{bind, Bindings};
/// fn quad_count<'a>(frame: &'a wgpu::Buffer, level: &'a wgpu::Buffer, flags: &'a wgpu::Buffer, counters: &'a wgpu::Buffer) -> impl Bindings<'a> {
///     bind::quad_count::Main { frame: frame.as_entire_binding(), level: level.as_entire_binding(), flags: flags.as_entire_binding(), quad_counters: counters.as_entire_binding() }
/// }
/// assert_eq!(bind::quad_count::Main::BINDINGS, &[("frame", 0), ("level", 1), ("flags", 2), ("quad_counters", 3)]);
/// ```
///
/// A binding left out:
///
/// ```compile_fail,E0063
/// use penumbra::research::gpu::stages::{bind, Bindings};
/// fn quad_count<'a>(frame: &'a wgpu::Buffer, level: &'a wgpu::Buffer, flags: &'a wgpu::Buffer) -> impl Bindings<'a> {
///     bind::quad_count::Main { frame: frame.as_entire_binding(), level: level.as_entire_binding(), flags: flags.as_entire_binding() }
/// }
/// ```
///
/// A binding misspelled:
///
/// ```compile_fail,E0560
/// use penumbra::research::gpu::stages::{bind, Bindings};
/// fn quad_count<'a>(frame: &'a wgpu::Buffer, level: &'a wgpu::Buffer, flags: &'a wgpu::Buffer, counters: &'a wgpu::Buffer) -> impl Bindings<'a> {
///     bind::quad_count::Main { frame: frame.as_entire_binding(), level: level.as_entire_binding(), flags: flags.as_entire_binding(), quad_counter: counters.as_entire_binding() }
/// }
/// ```
pub trait Bindings<'a> {
    /// The stage whose kernel declares the bindings.
    const STAGE: &'static str;
    /// The entry points that use exactly these bindings.
    const ENTRY_POINTS: &'static [&'static str];
    /// The bind group's entries, in the table's order.
    fn entries(self) -> Vec<wgpu::BindGroupEntry<'a>>;
}

/// `NAME = file kernel { flags }, split, [entries];` defines `Stage::NAME`, lists it in [`STAGES`]
/// and generates `bind::file`, its bindings structs. `kernel` embeds kernels/<file>.wgsl; `none` is
/// a stage without one. An entry is `compute Set(entry, …) WORKGROUP { variable: binding, … }`
/// (entry points that share a set of bindings share its struct `bind::file::Set`) or
/// `render(entry) { … }`; a render pipeline's layout is the union of its entries', and the entry
/// written `render Set(entry) { … }` (the vertex entry, whose bindings hold the fragment entry's)
/// gives its bind group's struct.
macro_rules! stage_table {
    ($($(#[$doc:meta])* $id:ident = $name:ident $kind:ident $({ $($flag:ident: $value:expr),* $(,)? })?, $split:expr, [$($entries:tt)*];)*) => {
        impl Stage {
            $($(#[$doc])* pub const $id: Stage = Stage {
                name: stringify!($name),
                kernel: stage_table!(@kernel $kind $name $({ $($flag: $value),* })?),
                entries: stage_table!(@entries $name [] $($entries)*),
                split: $split,
            };)*
        }

        /// Every stage, in frame order.
        pub(crate) const STAGES: &[Stage] = &[$(Stage::$id),*];

        /// The bindings structs of every compute entry point, a module per stage (see [`Bindings`]).
        pub mod bind {
            $(stage_table!(@module $name $($entries)*);)*
        }
    };
    (@kernel none $name:ident) => { None };
    (@kernel kernel $name:ident $({ $($flag:ident: $value:expr),* })?) => {
        Some(Kernel { $($($flag: $value,)*)? ..Kernel::plain(include_str!(concat!("../../kernels/", stringify!($name), ".wgsl"))) })
    };
    (@entries $stage:ident [$($done:expr),*] $(,)?) => { &[$($done),*] };
    (@entries $stage:ident [$($done:expr),*] compute $set:ident ($($ep:ident),+) $wg:ident { $($v:ident: $b:literal),* $(,)? } $(, $($rest:tt)*)?) => {
        stage_table!(@entries $stage [$($done,)* $(compute(stringify!($ep), $wg, bind::$stage::$set::BINDINGS)),+] $($($rest)*)?)
    };
    (@entries $stage:ident [$($done:expr),*] render $set:ident ($ep:ident) { $($v:ident: $b:literal),* $(,)? } $(, $($rest:tt)*)?) => {
        stage_table!(@entries $stage [$($done,)* render(stringify!($ep), bind::$stage::$set::BINDINGS)] $($($rest)*)?)
    };
    (@entries $stage:ident [$($done:expr),*] render ($ep:ident) { $($v:ident: $b:literal),* $(,)? } $(, $($rest:tt)*)?) => {
        stage_table!(@entries $stage [$($done,)* render(stringify!($ep), &[$((stringify!($v), $b)),*])] $($($rest)*)?)
    };
    (@module $stage:ident) => {};
    (@module $stage:ident $($entries:tt)+) => {
        #[doc = concat!("The bindings of `", stringify!($stage), "`'s compute entry points.")]
        pub mod $stage {
            stage_table!(@structs $stage $($entries)+);
        }
    };
    (@structs $stage:ident $(,)?) => {};
    (@structs $stage:ident compute $set:ident ($($ep:ident),+) $wg:ident { $($v:ident: $b:literal),* $(,)? } $(, $($rest:tt)*)?) => {
        #[doc = concat!("What `", stringify!($stage), "`", $("::", stringify!($ep), " ",)+ "reads and writes: each field is the WGSL variable of that name.")]
        pub struct $set<'a> {
            $(#[doc = concat!("@binding(", stringify!($b), ")")] pub $v: wgpu::BindingResource<'a>,)*
        }
        impl $set<'_> {
            /// (WGSL variable, @binding) of group 0, for the stage table.
            pub const BINDINGS: &'static [(&'static str, u32)] = &[$((stringify!($v), $b)),*];
        }
        impl<'a> crate::gpu::stages::Bindings<'a> for $set<'a> {
            const STAGE: &'static str = stringify!($stage);
            const ENTRY_POINTS: &'static [&'static str] = &[$(stringify!($ep)),+];
            fn entries(self) -> Vec<wgpu::BindGroupEntry<'a>> {
                vec![$(wgpu::BindGroupEntry { binding: $b, resource: self.$v }),*]
            }
        }
        stage_table!(@structs $stage $($($rest)*)?);
    };
    (@structs $stage:ident render $set:ident ($ep:ident) { $($v:ident: $b:literal),* $(,)? } $(, $($rest:tt)*)?) => {
        stage_table!(@structs $stage compute $set ($ep) render { $($v: $b),* } $(, $($rest)*)?);
    };
    (@structs $stage:ident render ($ep:ident) { $($v:ident: $b:literal),* $(,)? } $(, $($rest:tt)*)?) => {
        stage_table!(@structs $stage $($($rest)*)?);
    };
}

use Split::{Decision, Raster, Shade, Waits};
const PIXEL: [u32; 3] = PIXEL_WORKGROUP;
const LINE: [u32; 3] = LINE_WORKGROUP;
const SINGLE: [u32; 3] = SINGLE_WORKGROUP;

const CULL_RUN_GROUP: [u32; 3] = [CULL_RUN, 1, 1];

stage_table! {
    /// The camera G-buffer (position, normal, depth).
    GBUFFER = gbuffer kernel, Some(Raster), [
        render Pipeline(vs_main) { camera: 0 },
        render(fs_main) { camera: 0 },
    ];
    /// Depth-only raster of the shadow maps, one layer per light sample.
    SHADOW_RASTER = shadow_raster kernel, Some(Raster), [
        render Pipeline(vs_main) { samples: 0 },
        render(vs_far) {},
    ];
    /// V = Σ weight · lit over a set of maps (or from adaptive's masks), and the geometry tiles.
    SHADE = shade kernel { reads_maps: true }, Some(Shade), [
        compute GeometryTiles(geometry_tiles) PIXEL { frame: 0, gbuffer_position: 3, tile_list_build: 10 },
        compute Block(block16, block8, block4, block2, block1) PIXEL { frame: 0, block_samples: 1, block_weights: 2, gbuffer_position: 3, gbuffer_normal: 4, shadow_maps: 5, visibility: 6, tile_list: 11 },
        compute FromMasks(from_masks) PIXEL { frame: 0, gbuffer_position: 3, visibility: 6, masks: 7, weights: 8 },
    ];
    /// The sums of the error estimate of a fixed sample set (docs/error-estimate.md).
    ESTIMATE = estimate kernel { reads_maps: true }, Some(Shade), [
        compute Block(block16, block8, block4, block2, block1) PIXEL { frame: 0, block_samples: 1, block_weights: 2, block_split: 3, gbuffer_position: 4, gbuffer_normal: 5, shadow_maps: 6, sums: 7, tile_list: 8 },
    ];
    /// Adaptive's map lookups: lit bits of each pixel's lattice mask.
    SHADOW_TEST = shadow_test kernel { reads_maps: true }, Some(Shade), [
        compute FillBlocks(fill_blocks) SINGLE { level: 1, samples: 2, test_list: 3, lattice_state: 8, control_words: 9, blocks: 19, block_args: 20, tile_list: 21 },
        compute Block(block16, block8, block4, block2, block1, cube16, cube8, cube4, cube2, cube1) PIXEL { frame: 0, samples: 2, gbuffer_position: 4, gbuffer_normal: 5, shadow_maps: 6, masks: 7, block: 18, tile_list: 21 },
        compute Local(list, probes) LINE { frame: 0, samples: 2, gbuffer_position: 4, gbuffer_normal: 5, consulted: 10, lattice_lit: 11, maps_a: 12, maps_b: 13, work: 14, work_total: 15, quads: 16, control: 17 },
    ];
    /// Per (pixel, quad): how many of the quad's corners are lit.
    REPROJECT_COUNT = reproject_count kernel, Some(Decision), [
        compute Main(main) LINE { frame: 0, level: 1, quads: 2, masks: 3, counts: 5, control: 14, word_state: 15 },
        compute List(list) LINE { frame: 0, level: 1, quads: 2, masks: 3, items: 10, counts_atomic: 11, item_total: 13 },
        compute Last(last) LINE { level: 1, quads: 2, masks: 3, items: 10, visibility_fixed: 12, item_total: 13 },
        compute Begin(begin) SINGLE { level: 1, item_total: 13, control: 14, list_args: 16 },
    ];
    /// Low-quality flags: a pixel whose neighbours' counts disagree with its own.
    NEIGHBOURHOOD = neighbourhood kernel, Some(Decision), [
        compute Main(main) LINE { frame: 0, level: 1, counts: 2, flags: 3, word_state: 7 },
        compute List(list) LINE { frame: 0, level: 1, counts: 2, items: 4, flags_atomic: 5, item_total: 6, word_state: 7, quad_counters: 8 },
    ];
    /// Low-quality pixels per quad (atomics).
    QUAD_COUNT = quad_count kernel, Some(Decision), [
        compute Main(main) LINE { frame: 0, level: 1, flags: 2, quad_counters: 3 },
    ];
    /// Which quads split, their children and the samples they request.
    SUBDIVIDE = subdivide kernel, Some(Decision), [
        compute Main(main) LINE { level: 0, quads: 1, quad_counters: 2, next_quads: 3, control: 4, lattice_state: 5, new_samples: 6, sample_level: 7, split_base: 8, dispatch_args: 9, held: 10 },
    ];
    /// scope = local: the next level's items, uniform shares, scissor rectangles; `seed` starts the
    /// item list and `resolve` turns V's integer sums into V.
    COMPACT = compact kernel, Some(Decision), [
        compute Main(main, main_rects) LINE { frame: 0, level: 1, items: 2, counts: 3, split_base: 4, next_items: 5, control: 6, visibility_fixed: 7, next_quads: 8, samples: 9, rects: 10, gbuffer_position: 11, gbuffer_normal: 12, item_total: 14, probes: 16, tiles: 17 },
        compute Seed(seed) PIXEL { frame: 0, level: 1, next_items: 5, control: 6, gbuffer_position: 11 },
        compute Resolve(resolve) PIXEL { frame: 0, level: 1, visibility_fixed: 7, visibility: 13 },
    ];
    /// scope = local: uniform pixels of split quads test the new samples (the blind-spot fix).
    PROBE = probe kernel, Some(Decision), [
        compute Main(main) LINE { level: 1, probes: 2, quads: 3, masks: 4, items: 9, control: 10, visibility_fixed: 11, probe_total: 13 },
        compute Begin(begin) SINGLE { level: 1, control: 10, probe_total: 13, probe_args: 14 },
    ];
    /// cull = on: the culling tiles of a batch of maps, from every geometry pixel or a tile list's.
    FOOTPRINT = footprint kernel, Some(Raster), [
        compute Main(main) PIXEL { frame: 0, samples: 1, gbuffer_position: 2, gbuffer_normal: 3, tiles: 4, batch: 5 },
        compute Listed(listed) PIXEL { frame: 0, samples: 1, gbuffer_position: 2, gbuffer_normal: 3, tiles: 4, batch: 5, tile_list: 6 },
    ];
    /// Per new map, the triangles that can change a texel its pixels test.
    CULL = cull kernel, Some(Raster), [
        compute Main(main) LINE { cull: 0, frame: 1, samples: 2, tiles: 3, runs: 4, slots: 6, args: 8, kept_runs: 10, control: 11 },
        compute Begin(begin) SINGLE { control: 11, dispatch: 12 },
        compute Triangles(triangles) CULL_RUN_GROUP { cull: 0, frame: 1, samples: 2, tiles: 3, indices: 5, slots: 6, culled: 7, args: 8, positions: 9, kept_runs: 10, control: 11 },
    ];
    /// The samples' weights from the leaves of the quad tree, on the GPU.
    WEIGHTS = weights kernel, Some(Decision), [
        compute LeavesOfLevel(leaves_of_level) LINE { level: 0, quads: 1, split_base: 2, leaves: 3, leaf_count: 4 },
        compute Main(main) SINGLE { leaves: 3, leaf_count: 4, rule: 5, lattice_state: 6, sample_level: 7, numerators: 8, weights: 9 },
    ];
    /// Depth-only shadow maps in compute kernels, many maps per chain, exact rules (docs/gpu-frame.md §7).
    RASTER_COMPUTE = raster_compute kernel, Some(Raster), [
        compute Clear(clear) LINE { params: 0, depth: 5 },
        compute Main(main) LINE { params: 0, samples: 1, jobs: 2, positions: 3, indices: 4, depth: 5, large: 6, control: 7, runs: 14, kept_counts: 15 },
        compute MainMaps(main_maps) LINE { params: 0, samples: 1, jobs: 2, positions: 3, indices: 4, depth: 5, large: 6, control: 7, request_control: 9, runs: 14 },
        compute Begin(begin) SINGLE { params: 0, control: 7, dispatch: 8 },
        compute LargeTiles(large_tiles) LINE { params: 0, samples: 1, jobs: 2, positions: 3, indices: 4, depth: 5, large: 6, control: 7 },
        compute Requested(requested) SINGLE { params: 0, jobs: 2, request_control: 9, request_list: 10, steer_args: 11 },
        compute KeptExtent(kept_extent) SINGLE { params: 0, jobs: 2, steer_args: 11, kept_counts: 15 },
        compute Store(store) LINE { params: 0, jobs: 2, depth: 5, layers: 12, layer_samples: 13 },
    ];
    /// Percentage-closer filtering.
    PCF = pcf kernel { reads_maps: true, pcf_taps: true }, Some(Shade), [
        compute Main(main) PIXEL { frame: 0, settings: 1, samples: 2, gbuffer_position: 3, gbuffer_normal: 4, shadow_maps: 5, disk: 6, visibility: 7, compare_sampler: 8 },
    ];
    /// The sun's cascaded shadow maps: a cascade per pixel by view depth, then its map.
    CASCADES = cascades kernel { reads_maps: true, pcf_taps: true }, Some(Shade), [
        compute Main(main) PIXEL { frame: 0, settings: 1, samples: 2, gbuffer_position: 3, gbuffer_normal: 4, shadow_maps: 5, disk: 6, visibility: 7, compare_sampler: 8, cascades: 9, chosen: 10 },
    ];
    /// Percentage-closer soft shadows.
    PCSS = pcss kernel { reads_maps: true }, Some(Shade), [
        compute Main(main) PIXEL { frame: 0, settings: 1, samples: 2, gbuffer_position: 3, gbuffer_normal: 4, shadow_maps: 5, visibility: 6 },
    ];
    /// regions: each screen region's sample count and texel need from a blocker search on the
    /// centre map, then each geometry tile's class and the classes' tile lists (docs/regions.md).
    REGIONS = regions kernel { reads_maps: true }, Some(Decision), [
        compute Measure(measure) PIXEL { frame: 0, params: 1, samples: 2, gbuffer_position: 3, gbuffer_normal: 4, shadow_maps: 5, regions: 6 },
        compute Total(total) LINE { params: 1, regions: 6, totals: 10 },
        compute Classify(classify) LINE { frame: 0, params: 1, regions: 6, tile_list: 7, classes: 8, class_tiles: 9, totals: 10 },
    ];
    /// The filtered methods' moment maps from the raster.
    MOMENTS = moments kernel { reads_raster: true }, Some(Raster), [
        compute Main(main) PIXEL { frame: 0, settings: 1, samples: 2, shadow_maps: 3, moments: 4 },
    ];
    /// Separable blur of the moment maps.
    BLUR = blur kernel, Some(Raster), [
        compute Blur(horizontal, vertical) PIXEL { frame: 0, settings: 1, source: 2, destination: 3 },
    ];
    /// V from the blurred moments.
    RECONSTRUCT = reconstruct kernel, Some(Shade), [
        compute Main(main) PIXEL { frame: 0, settings: 1, samples: 2, gbuffer_position: 3, gbuffer_normal: 4, moments: 5, visibility: 6 },
    ];
    /// Environment lighting: rays against the BVH, per pixel or per vertex.
    ENV_TRACE = env_trace kernel { environment: true }, Some(Shade), [
        compute Main(main) PIXEL { params: 0, gbuffer_position: 1, gbuffer_normal: 2, lights: 3, visibility: 4, blocked: 5, ao: 6, sums: 7, bvh_nodes: 20, bvh_triangles: 21 },
        compute Vertex(vertex) LINE { params: 0, lights: 3, blocked: 5, sums: 7, scene_vertices: 8, vertex_visibility: 9, bvh_nodes: 20, bvh_triangles: 21 },
    ];
    /// Triangle ids and barycentrics per pixel (per-vertex environment lighting).
    BARYCENTRICS = barycentrics kernel, Some(Raster), [
        render Pipeline(vs_main) { camera: 0, scene_vertices: 1, scene_indices: 2 },
        render(fs_main) {},
    ];
    /// Per-vertex visibility interpolated to the pixels.
    ENV_VERTEX_INTERP = env_vertex_interp kernel { environment: true }, Some(Shade), [
        compute Main(main) PIXEL { params: 0, triangle_ids: 1, scene_indices: 2, vertex_visibility: 3, ao: 4, visibility: 5 },
    ];
    /// Environment adaptive: disagreeing corner rays per panorama cell.
    ENV_COUNT = env_count kernel { environment: true }, Some(Decision), [
        compute Main(main) LINE { params: 0, gbuffer_position: 1, gbuffer_normal: 2, corners: 3, cells: 4, counts: 5, bvh_nodes: 20, bvh_triangles: 21 },
    ];
    /// Environment adaptive: which cells split.
    ENV_SPLIT = env_split kernel { environment: true }, Some(Decision), [
        compute Main(main) LINE { params: 0, cells: 1, counts: 2, cell_power: 3, next_cells: 4, leaves: 5, control: 6 },
    ];
    /// Environment lighting from one shadow map per light, PCF-filtered.
    ENV_SHADOWMAPS = env_shadowmaps kernel { environment: true, pcf_taps: true, reads_raster: true }, Some(Shade), [
        compute Main(main) PIXEL { frame: 0, params: 1, samples: 2, gbuffer_position: 3, gbuffer_normal: 4, shadow_maps: 5, lights: 6, visibility: 7, ao: 8, settings: 9, disk: 10, compare_sampler: 11 },
    ];
    /// The reference's own integrator at listed surface points, through the environment's BVH:
    /// lit samples per point, the exact truth a certified error samples (docs/certify.md).
    TRUTH_TRACE = truth_trace kernel { environment: true }, Some(Decision), [
        compute Main(main) LINE { params: 0, points: 1, counts: 2, truth_triangles: 3, bvh_nodes: 20 },
    ];
    /// Screen-space ambient occlusion.
    SSAO = ssao kernel { environment: true }, Some(Shade), [
        compute Main(main) PIXEL { params: 0, camera: 1, gbuffer_position: 2, gbuffer_normal: 3, kernel: 4, ao: 5, occluded: 6 },
    ];
    /// The hybrid map store built from the raster (docs/hybrid.md).
    HYBRID_BUILD = hybrid_build kernel { reads_raster: true }, Some(Raster), [
        compute Classify(classify) PIXEL { build: 0, raster: 1, offsets: 2, coarse_nodes: 6, gather_sampler: 7 },
        compute ScanRows(scan_rows) LINE { build: 0, offsets: 2, row_starts: 3 },
        compute ScanTotal(scan_total) SINGLE { build: 0, row_starts: 3, control: 4, pool: 5 },
        compute Emit(emit) PIXEL { build: 0, raster: 1, offsets: 2, row_starts: 3, control: 4, pool: 5, coarse_nodes: 6, gather_sampler: 7 },
    ];
    /// SSAO's copy of V before it multiplies.
    SSAO_COPY = ssao_copy none, Some(Shade), [];
    /// Adaptive's one read-back per level: the loop decides the next level from it.
    READBACK_LEVEL = readback_level none, Some(Decision), [];
    /// Environment adaptive's read-backs of its counters and leaves.
    ENV_READBACK = env_readback none, Some(Decision), [];
    /// Environment adaptive: the leaves as lights (CPU).
    ENV_LIGHTS = env_lights none, Some(Decision), [];
    /// V read back after the frame.
    READBACK = readback none, Some(Waits), [];
    /// Adaptive's pictures read back (scope = local, when pictures are asked for).
    PICTURES = pictures none, Some(Waits), [];
    /// Scene upload and per-frame setup, outside the frame.
    SETUP = setup none, None, [];
    /// Pipeline creation (the first frame of a renderer), outside the frame.
    BUILD = build none, None, [];
    /// Geometry upload (the first frame of a renderer), outside the frame.
    UPLOAD = upload none, None, [];
}

/// The frame split (raster, decision, shade, waits) from per-stage times; `other` only for a name
/// the table does not know (rows written by an older build). Meaningful from a stages-mode frame,
/// whose stages hold their waits.
pub fn frame_split(
    stages_ms: &std::collections::BTreeMap<String, f64>,
) -> std::collections::BTreeMap<&'static str, f64> {
    let mut out: std::collections::BTreeMap<&'static str, f64> =
        Split::ALL.iter().map(|s| (s.name(), 0.0)).collect();
    for (name, ms) in stages_ms {
        match Stage::named(name) {
            Some(Stage {
                split: Some(part), ..
            }) => *out.entry(part.name()).or_insert(0.0) += ms,
            Some(_) => {}
            None => *out.entry("other").or_insert(0.0) += ms,
        }
    }
    out
}

/// The frame split's decision part: what `run.json` reports as `decision_stages_ms`, and over the
/// frame as `decision_share`.
pub fn decision_ms(stages_ms: &std::collections::BTreeMap<String, f64>) -> f64 {
    // An empty f64 sum is -0.0; + 0.0 makes a method without decisions report 0.
    stages_ms
        .iter()
        .filter(|(k, _)| Stage::named(k).is_some_and(|s| s.split == Some(Decision)))
        .map(|(_, v)| v)
        .sum::<f64>()
        + 0.0
}

/// Whether `name` is timed outside the frame (setup, build, upload): kept apart from its stages.
pub fn outside_frame(name: &str) -> bool {
    Stage::named(name).is_some_and(|s| s.split.is_none())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    #[test]
    fn names_are_unique_and_kernel_stages_have_entries() {
        for (i, s) in STAGES.iter().enumerate() {
            assert!(
                STAGES[..i].iter().all(|t| t.name != s.name),
                "{} listed twice",
                s.name
            );
            assert_eq!(
                s.kernel.is_some(),
                !s.entries.is_empty(),
                "{}: a kernel has entry points, host work none",
                s.name
            );
        }
    }

    #[test]
    fn every_frame_stage_has_a_part_and_setup_has_none() {
        let stages: BTreeMap<String, f64> = [
            ("gbuffer", 1.0),
            ("shadow_raster", 2.0),
            ("cull", 4.0),
            ("subdivide", 8.0),
            ("shadow_test", 16.0),
            ("readback_level", 32.0),
            ("readback", 64.0),
            ("setup", 128.0),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect();
        let split = frame_split(&stages);
        assert_eq!(split["raster"], 7.0);
        assert_eq!(split["decision"], 40.0);
        assert_eq!(split["shade"], 16.0);
        assert_eq!(split["waits"], 64.0);
        assert!(!split.contains_key("other"));
        // One definition: the decision share's stages are the split's decision part.
        assert_eq!(decision_ms(&stages), split["decision"]);
        assert!(
            outside_frame("setup")
                && outside_frame("build")
                && outside_frame("upload")
                && !outside_frame("readback")
        );
        assert_eq!(
            frame_split(&[("retired".to_string(), 1.0)].into_iter().collect())["other"],
            1.0
        );
        assert_eq!(decision_ms(&BTreeMap::new()).to_bits(), 0f64.to_bits());
    }
}
