//! The stage table: every stage of a frame, once. A stage's name is its WGSL file, its pass and
//! twin modules, its debug label, its timing key and its key in `run.json`'s `stages_ms`; the
//! table also gives its kernel, its entry points (workgroup size and bindings, by the WGSL
//! variable's name) and its part of the frame split. The kernel registry (`gpu::kernels`), the
//! timer (`gpu::timing`), the passes' bindings (`stages::ComputeKernel`) and the naga tests
//! (tests/kernels.rs) all read it, so adding a stage is its kernel file, its pass and one entry
//! here (and its CPU twin).

/// 2D pixel kernels.
pub const PIXEL_WORKGROUP: [u32; 3] = [8, 8, 1];
/// 1D kernels over words, items or quads.
pub const LINE_WORKGROUP: [u32; 3] = [64, 1, 1];
/// One invocation: kernels that write a few counters or dispatch arguments.
pub const SINGLE_WORKGROUP: [u32; 3] = [1, 1, 1];
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
        Self { body, reads_maps: false, reads_raster: false, environment: false, pcf_taps: false }
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

impl Entry {
    /// The @binding of the WGSL variable `name`, if this entry point uses it.
    pub fn binding(&self, name: &str) -> Option<u32> {
        self.bindings.iter().find(|(n, _)| *n == name).map(|&(_, b)| b)
    }
}

const fn compute(name: &'static str, workgroup: [u32; 3], bindings: &'static [(&'static str, u32)]) -> Entry {
    Entry { name, workgroup: Some(workgroup), bindings }
}

const fn render(name: &'static str, bindings: &'static [(&'static str, u32)]) -> Entry {
    Entry { name, workgroup: None, bindings }
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

    /// The @binding of the WGSL variable `name` in any of the stage's entry points (a render
    /// pipeline's layout is the union of its vertex and fragment entries').
    pub fn binding(&self, name: &str) -> Option<u32> {
        self.entries.iter().find_map(|e| e.binding(name))
    }
}

/// `name = "file" kernel { flags }, split, [entries];` defines `Stage::NAME` and lists it in
/// [`STAGES`]. `kernel` embeds kernels/<file>.wgsl; `none` is a stage without one.
macro_rules! stage_table {
    ($($(#[$doc:meta])* $id:ident = $name:literal $kind:ident $({ $($flag:ident: $value:expr),* $(,)? })?, $split:expr, [$($entry:expr),* $(,)?];)*) => {
        impl Stage {
            $($(#[$doc])* pub const $id: Stage = Stage {
                name: $name,
                kernel: stage_table!(@kernel $kind $name $({ $($flag: $value),* })?),
                entries: &[$($entry),*],
                split: $split,
            };)*
        }

        /// Every stage, in frame order.
        pub const STAGES: &[Stage] = &[$(Stage::$id),*];
    };
    (@kernel none $name:literal) => { None };
    (@kernel kernel $name:literal $({ $($flag:ident: $value:expr),* })?) => {
        Some(Kernel { $($($flag: $value,)*)? ..Kernel::plain(include_str!(concat!("../../kernels/", $name, ".wgsl"))) })
    };
}

use Split::{Decision, Raster, Shade, Waits};
const PIXEL: [u32; 3] = PIXEL_WORKGROUP;
const LINE: [u32; 3] = LINE_WORKGROUP;
const SINGLE: [u32; 3] = SINGLE_WORKGROUP;

const SHADE_BLOCK: &[(&str, u32)] = &[
    ("frame", 0), ("block_samples", 1), ("block_weights", 2), ("gbuffer_position", 3), ("gbuffer_normal", 4), ("shadow_maps", 5), ("visibility", 6), ("tile_list", 11),
];
const TEST_BLOCK: &[(&str, u32)] =
    &[("frame", 0), ("samples", 2), ("gbuffer_position", 4), ("gbuffer_normal", 5), ("shadow_maps", 6), ("masks", 7), ("block", 18), ("tile_list", 21)];
const TEST_LOCAL: &[(&str, u32)] = &[
    ("frame", 0), ("samples", 2), ("gbuffer_position", 4), ("gbuffer_normal", 5), ("consulted", 10), ("lattice_lit", 11), ("maps_a", 12), ("maps_b", 13), ("work", 14), ("work_total", 15), ("quads", 16), ("control", 17),
];
const COMPACT_MAIN: &[(&str, u32)] = &[
    ("frame", 0), ("level", 1), ("items", 2), ("counts", 3), ("split_base", 4), ("next_items", 5), ("control", 6), ("visibility_fixed", 7), ("next_quads", 8), ("samples", 9), ("rects", 10), ("gbuffer_position", 11), ("gbuffer_normal", 12), ("item_total", 14), ("probes", 16), ("tiles", 17),
];
const ESTIMATE_BLOCK: &[(&str, u32)] = &[
    ("frame", 0), ("block_samples", 1), ("block_weights", 2), ("block_split", 3), ("gbuffer_position", 4), ("gbuffer_normal", 5), ("shadow_maps", 6), ("sums", 7), ("tile_list", 8),
];
const BLUR: &[(&str, u32)] = &[("frame", 0), ("settings", 1), ("source", 2), ("destination", 3)];

stage_table! {
    /// The camera G-buffer (position, normal, depth).
    GBUFFER = "gbuffer" kernel, Some(Raster), [render("vs_main", &[("camera", 0)]), render("fs_main", &[("camera", 0)])];
    /// Depth-only raster of the shadow maps, one layer per light sample.
    SHADOW_RASTER = "shadow_raster" kernel, Some(Raster), [render("vs_main", &[("samples", 0)])];
    /// V = Σ weight · lit over a set of maps (or from adaptive's masks), and the geometry tiles.
    SHADE = "shade" kernel { reads_maps: true }, Some(Shade), [
        compute("geometry_tiles", PIXEL, &[("frame", 0), ("gbuffer_position", 3), ("tile_list_build", 10)]),
        compute("block16", PIXEL, SHADE_BLOCK),
        compute("block8", PIXEL, SHADE_BLOCK),
        compute("block4", PIXEL, SHADE_BLOCK),
        compute("block2", PIXEL, SHADE_BLOCK),
        compute("block1", PIXEL, SHADE_BLOCK),
        compute("from_masks", PIXEL, &[("frame", 0), ("gbuffer_position", 3), ("visibility", 6), ("masks", 7), ("weights", 8)]),
    ];
    /// The sums of the error estimate of a fixed sample set (docs/error-estimate.md).
    ESTIMATE = "estimate" kernel { reads_maps: true }, Some(Shade), [
        compute("block16", PIXEL, ESTIMATE_BLOCK),
        compute("block8", PIXEL, ESTIMATE_BLOCK),
        compute("block4", PIXEL, ESTIMATE_BLOCK),
        compute("block2", PIXEL, ESTIMATE_BLOCK),
        compute("block1", PIXEL, ESTIMATE_BLOCK),
    ];
    /// Adaptive's map lookups: lit bits of each pixel's lattice mask.
    SHADOW_TEST = "shadow_test" kernel { reads_maps: true }, Some(Shade), [
        compute("fill_blocks", SINGLE, &[("level", 1), ("samples", 2), ("test_list", 3), ("lattice_state", 8), ("control_words", 9), ("blocks", 19), ("block_args", 20), ("tile_list", 21)]),
        compute("block16", PIXEL, TEST_BLOCK),
        compute("block8", PIXEL, TEST_BLOCK),
        compute("block4", PIXEL, TEST_BLOCK),
        compute("block2", PIXEL, TEST_BLOCK),
        compute("block1", PIXEL, TEST_BLOCK),
        compute("cube16", PIXEL, TEST_BLOCK),
        compute("cube8", PIXEL, TEST_BLOCK),
        compute("cube4", PIXEL, TEST_BLOCK),
        compute("cube2", PIXEL, TEST_BLOCK),
        compute("cube1", PIXEL, TEST_BLOCK),
        compute("list", LINE, TEST_LOCAL),
        compute("probes", LINE, TEST_LOCAL),
    ];
    /// Per (pixel, quad): how many of the quad's corners are lit.
    REPROJECT_COUNT = "reproject_count" kernel, Some(Decision), [
        compute("main", LINE, &[("frame", 0), ("level", 1), ("quads", 2), ("masks", 3), ("counts", 5), ("control", 14), ("word_state", 15)]),
        compute("list", LINE, &[("frame", 0), ("level", 1), ("quads", 2), ("masks", 3), ("items", 10), ("counts_atomic", 11), ("item_total", 13)]),
        compute("last", LINE, &[("level", 1), ("quads", 2), ("masks", 3), ("items", 10), ("visibility_fixed", 12), ("item_total", 13)]),
        compute("begin", SINGLE, &[("level", 1), ("item_total", 13), ("control", 14), ("list_args", 16)]),
    ];
    /// Low-quality flags: a pixel whose neighbours' counts disagree with its own.
    NEIGHBOURHOOD = "neighbourhood" kernel, Some(Decision), [
        compute("main", LINE, &[("frame", 0), ("level", 1), ("counts", 2), ("flags", 3), ("word_state", 7)]),
        compute("list", LINE, &[("frame", 0), ("level", 1), ("counts", 2), ("items", 4), ("flags_atomic", 5), ("item_total", 6), ("word_state", 7), ("quad_counters", 8)]),
    ];
    /// Low-quality pixels per quad (atomics).
    QUAD_COUNT = "quad_count" kernel, Some(Decision), [
        compute("main", LINE, &[("frame", 0), ("level", 1), ("flags", 2), ("quad_counters", 3)]),
    ];
    /// Which quads split, their children and the samples they request.
    SUBDIVIDE = "subdivide" kernel, Some(Decision), [
        compute("main", LINE, &[("level", 0), ("quads", 1), ("quad_counters", 2), ("next_quads", 3), ("control", 4), ("lattice_state", 5), ("new_samples", 6), ("sample_level", 7), ("split_base", 8), ("dispatch_args", 9)]),
    ];
    /// scope = local: the next level's items, uniform shares, scissor rectangles; `seed` starts the
    /// item list and `resolve` turns V's integer sums into V.
    COMPACT = "compact" kernel, Some(Decision), [
        compute("main", LINE, COMPACT_MAIN),
        compute("main_rects", LINE, COMPACT_MAIN),
        compute("seed", PIXEL, &[("frame", 0), ("level", 1), ("next_items", 5), ("control", 6), ("gbuffer_position", 11)]),
        compute("resolve", PIXEL, &[("frame", 0), ("level", 1), ("visibility_fixed", 7), ("visibility", 13)]),
    ];
    /// scope = local: uniform pixels of split quads test the new samples (the blind-spot fix).
    PROBE = "probe" kernel, Some(Decision), [
        compute("main", LINE, &[("level", 1), ("probes", 2), ("quads", 3), ("masks", 4), ("items", 9), ("control", 10), ("visibility_fixed", 11), ("probe_total", 13)]),
        compute("begin", SINGLE, &[("level", 1), ("control", 10), ("probe_total", 13), ("probe_args", 14)]),
    ];
    /// cull = on where every geometry pixel tests every map: the culling tiles of a batch of maps.
    FOOTPRINT = "footprint" kernel, Some(Raster), [
        compute("main", PIXEL, &[("frame", 0), ("samples", 1), ("gbuffer_position", 2), ("gbuffer_normal", 3), ("tiles", 4), ("batch", 5)]),
    ];
    /// Per new map, the triangles that can change a texel its pixels test.
    CULL = "cull" kernel, Some(Raster), [
        compute("main", LINE, &[("cull", 0), ("frame", 1), ("samples", 2), ("tiles", 3), ("runs", 4), ("slots", 6), ("args", 8), ("kept_runs", 10), ("control", 11)]),
        compute("begin", SINGLE, &[("control", 11), ("dispatch", 12)]),
        compute("triangles", [CULL_RUN, 1, 1], &[("cull", 0), ("frame", 1), ("samples", 2), ("tiles", 3), ("indices", 5), ("slots", 6), ("culled", 7), ("args", 8), ("positions", 9), ("kept_runs", 10), ("control", 11)]),
    ];
    /// The samples' weights from the leaves of the quad tree, on the GPU.
    WEIGHTS = "weights" kernel, Some(Decision), [
        compute("leaves_of_level", LINE, &[("level", 0), ("quads", 1), ("split_base", 2), ("leaves", 3), ("leaf_count", 4)]),
        compute("main", SINGLE, &[("leaves", 3), ("leaf_count", 4), ("rule", 5), ("lattice_state", 6), ("sample_level", 7), ("numerators", 8), ("weights", 9)]),
    ];
    /// Depth-only shadow maps in compute kernels, many maps per chain, exact rules (docs/gpu-frame.md §7).
    RASTER_COMPUTE = "raster_compute" kernel, Some(Raster), [
        compute("clear", LINE, &[("params", 0), ("depth", 5)]),
        compute("main", LINE, &[("params", 0), ("samples", 1), ("jobs", 2), ("positions", 3), ("indices", 4), ("depth", 5), ("large", 6), ("control", 7), ("runs", 14), ("kept_counts", 15)]),
        compute("main_maps", LINE, &[("params", 0), ("samples", 1), ("jobs", 2), ("positions", 3), ("indices", 4), ("depth", 5), ("large", 6), ("control", 7), ("request_control", 9), ("runs", 14)]),
        compute("begin", SINGLE, &[("params", 0), ("control", 7), ("dispatch", 8)]),
        compute("large_tiles", LINE, &[("params", 0), ("samples", 1), ("jobs", 2), ("positions", 3), ("indices", 4), ("depth", 5), ("large", 6), ("control", 7)]),
        compute("requested", SINGLE, &[("params", 0), ("jobs", 2), ("request_control", 9), ("request_list", 10), ("steer_args", 11)]),
        compute("kept_extent", SINGLE, &[("params", 0), ("jobs", 2), ("steer_args", 11), ("kept_counts", 15)]),
        compute("store", LINE, &[("params", 0), ("jobs", 2), ("depth", 5), ("layers", 12), ("layer_samples", 13)]),
    ];
    /// Percentage-closer filtering.
    PCF = "pcf" kernel { reads_maps: true, pcf_taps: true }, Some(Shade), [
        compute("main", PIXEL, &[("frame", 0), ("settings", 1), ("samples", 2), ("gbuffer_position", 3), ("gbuffer_normal", 4), ("shadow_maps", 5), ("disk", 6), ("visibility", 7), ("compare_sampler", 8)]),
    ];
    /// The sun's cascaded shadow maps: a cascade per pixel by view depth, then its map.
    CASCADES = "cascades" kernel { reads_maps: true, pcf_taps: true }, Some(Shade), [
        compute("main", PIXEL, &[("frame", 0), ("settings", 1), ("samples", 2), ("gbuffer_position", 3), ("gbuffer_normal", 4), ("shadow_maps", 5), ("disk", 6), ("visibility", 7), ("compare_sampler", 8), ("cascades", 9), ("chosen", 10)]),
    ];
    /// Percentage-closer soft shadows.
    PCSS = "pcss" kernel { reads_maps: true }, Some(Shade), [
        compute("main", PIXEL, &[("frame", 0), ("settings", 1), ("samples", 2), ("gbuffer_position", 3), ("gbuffer_normal", 4), ("shadow_maps", 5), ("visibility", 6)]),
    ];
    /// regions: each screen region's sample count and texel need from a blocker search on the
    /// centre map, then each geometry tile's class and the classes' tile lists (docs/regions.md).
    REGIONS = "regions" kernel { reads_maps: true }, Some(Decision), [
        compute("measure", PIXEL, &[("frame", 0), ("params", 1), ("samples", 2), ("gbuffer_position", 3), ("gbuffer_normal", 4), ("shadow_maps", 5), ("regions", 6)]),
        compute("total", LINE, &[("params", 1), ("regions", 6), ("totals", 10)]),
        compute("classify", LINE, &[("frame", 0), ("params", 1), ("regions", 6), ("tile_list", 7), ("classes", 8), ("class_tiles", 9), ("totals", 10)]),
    ];
    /// The filtered methods' moment maps from the raster.
    MOMENTS = "moments" kernel { reads_raster: true }, Some(Raster), [
        compute("main", PIXEL, &[("frame", 0), ("settings", 1), ("samples", 2), ("shadow_maps", 3), ("moments", 4)]),
    ];
    /// Separable blur of the moment maps.
    BLUR = "blur" kernel, Some(Raster), [compute("horizontal", PIXEL, BLUR), compute("vertical", PIXEL, BLUR)];
    /// V from the blurred moments.
    RECONSTRUCT = "reconstruct" kernel, Some(Shade), [
        compute("main", PIXEL, &[("frame", 0), ("settings", 1), ("samples", 2), ("gbuffer_position", 3), ("gbuffer_normal", 4), ("moments", 5), ("visibility", 6)]),
    ];
    /// Environment lighting: rays against the BVH, per pixel or per vertex.
    ENV_TRACE = "env_trace" kernel { environment: true }, Some(Shade), [
        compute("main", PIXEL, &[("params", 0), ("gbuffer_position", 1), ("gbuffer_normal", 2), ("lights", 3), ("visibility", 4), ("blocked", 5), ("ao", 6), ("sums", 7), ("bvh_nodes", 20), ("bvh_triangles", 21)]),
        compute("vertex", LINE, &[("params", 0), ("lights", 3), ("blocked", 5), ("sums", 7), ("scene_vertices", 8), ("vertex_visibility", 9), ("bvh_nodes", 20), ("bvh_triangles", 21)]),
    ];
    /// Triangle ids and barycentrics per pixel (per-vertex environment lighting).
    BARYCENTRICS = "barycentrics" kernel, Some(Raster), [
        render("vs_main", &[("camera", 0), ("scene_vertices", 1), ("scene_indices", 2)]),
        render("fs_main", &[]),
    ];
    /// Per-vertex visibility interpolated to the pixels.
    ENV_VERTEX_INTERP = "env_vertex_interp" kernel { environment: true }, Some(Shade), [
        compute("main", PIXEL, &[("params", 0), ("triangle_ids", 1), ("scene_indices", 2), ("vertex_visibility", 3), ("ao", 4), ("visibility", 5)]),
    ];
    /// Environment adaptive: disagreeing corner rays per panorama cell.
    ENV_COUNT = "env_count" kernel { environment: true }, Some(Decision), [
        compute("main", LINE, &[("params", 0), ("gbuffer_position", 1), ("gbuffer_normal", 2), ("corners", 3), ("cells", 4), ("counts", 5), ("bvh_nodes", 20), ("bvh_triangles", 21)]),
    ];
    /// Environment adaptive: which cells split.
    ENV_SPLIT = "env_split" kernel { environment: true }, Some(Decision), [
        compute("main", LINE, &[("params", 0), ("cells", 1), ("counts", 2), ("cell_power", 3), ("next_cells", 4), ("leaves", 5), ("control", 6)]),
    ];
    /// Environment lighting from one shadow map per light, PCF-filtered.
    ENV_SHADOWMAPS = "env_shadowmaps" kernel { environment: true, pcf_taps: true, reads_raster: true }, Some(Shade), [
        compute("main", PIXEL, &[("frame", 0), ("params", 1), ("samples", 2), ("gbuffer_position", 3), ("gbuffer_normal", 4), ("shadow_maps", 5), ("lights", 6), ("visibility", 7), ("ao", 8), ("settings", 9), ("disk", 10), ("compare_sampler", 11)]),
    ];
    /// Screen-space ambient occlusion.
    SSAO = "ssao" kernel { environment: true }, Some(Shade), [
        compute("main", PIXEL, &[("params", 0), ("camera", 1), ("gbuffer_position", 2), ("gbuffer_normal", 3), ("kernel", 4), ("ao", 5), ("occluded", 6)]),
    ];
    /// The hybrid map store built from the raster (docs/hybrid.md).
    HYBRID_BUILD = "hybrid_build" kernel { reads_raster: true }, Some(Raster), [
        compute("classify", PIXEL, &[("build", 0), ("raster", 1), ("offsets", 2), ("coarse_nodes", 6), ("gather_sampler", 7)]),
        compute("scan_rows", LINE, &[("build", 0), ("offsets", 2), ("row_starts", 3)]),
        compute("scan_total", SINGLE, &[("build", 0), ("row_starts", 3), ("control", 4), ("pool", 5)]),
        compute("emit", PIXEL, &[("build", 0), ("raster", 1), ("offsets", 2), ("row_starts", 3), ("control", 4), ("pool", 5), ("coarse_nodes", 6), ("gather_sampler", 7)]),
    ];
    /// SSAO's copy of V before it multiplies.
    SSAO_COPY = "ssao_copy" none, Some(Shade), [];
    /// Adaptive's one read-back per level: the loop decides the next level from it.
    READBACK_LEVEL = "readback_level" none, Some(Decision), [];
    /// Environment adaptive's read-backs of its counters and leaves.
    ENV_READBACK = "env_readback" none, Some(Decision), [];
    /// Environment adaptive: the leaves as lights (CPU).
    ENV_LIGHTS = "env_lights" none, Some(Decision), [];
    /// V read back after the frame.
    READBACK = "readback" none, Some(Waits), [];
    /// Adaptive's pictures read back (scope = local, when pictures are asked for).
    PICTURES = "pictures" none, Some(Waits), [];
    /// Scene upload and per-frame setup, outside the frame.
    SETUP = "setup" none, None, [];
    /// Pipeline creation (the first frame of a renderer), outside the frame.
    BUILD = "build" none, None, [];
    /// Geometry upload (the first frame of a renderer), outside the frame.
    UPLOAD = "upload" none, None, [];
}

/// The frame split (raster, decision, shade, waits) from per-stage times; `other` only for a name
/// the table does not know (rows written by an older build). Meaningful from a stages-mode frame,
/// whose stages hold their waits.
pub fn frame_split(stages_ms: &std::collections::BTreeMap<String, f64>) -> std::collections::BTreeMap<&'static str, f64> {
    let mut out: std::collections::BTreeMap<&'static str, f64> = Split::ALL.iter().map(|s| (s.name(), 0.0)).collect();
    for (name, ms) in stages_ms {
        match Stage::named(name) {
            Some(Stage { split: Some(part), .. }) => *out.entry(part.name()).or_insert(0.0) += ms,
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
    stages_ms.iter().filter(|(k, _)| Stage::named(k).is_some_and(|s| s.split == Some(Decision))).map(|(_, v)| v).sum::<f64>() + 0.0
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
            assert!(STAGES[..i].iter().all(|t| t.name != s.name), "{} listed twice", s.name);
            assert_eq!(s.kernel.is_some(), !s.entries.is_empty(), "{}: a kernel has entry points, host work none", s.name);
        }
    }

    #[test]
    fn every_frame_stage_has_a_part_and_setup_has_none() {
        let stages: BTreeMap<String, f64> = [
            ("gbuffer", 1.0), ("shadow_raster", 2.0), ("cull", 4.0), ("subdivide", 8.0), ("shadow_test", 16.0), ("readback_level", 32.0), ("readback", 64.0), ("setup", 128.0),
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
        assert!(outside_frame("setup") && outside_frame("build") && outside_frame("upload") && !outside_frame("readback"));
        assert_eq!(frame_split(&[("retired".to_string(), 1.0)].into_iter().collect())["other"], 1.0);
        assert_eq!(decision_ms(&BTreeMap::new()).to_bits(), 0f64.to_bits());
    }
}
