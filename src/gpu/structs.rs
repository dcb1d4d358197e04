//! `#[repr(C)]` Pod twins of the WGSL structs. A test reads the WGSL layout through naga and
//! compares every member offset and the size with these, so the two cannot drift apart silently.

use bytemuck::{Pod, Zeroable};

/// `GpuFrame.flags`: the facing test is on (`self_shadow = "facing"`).
pub const FRAME_FACING_TEST: u32 = 1;
/// `GpuFrame.flags`: a point light lights every way; no plane through `light_center` bounds its
/// lit side.
pub const FRAME_EVERY_WAY: u32 = 2;

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuFrame {
    pub width: u32,
    pub height: u32,
    pub map_size: u32,
    pub flags: u32,
    pub light_center: [f32; 4],
    pub light_normal: [f32; 4],
    pub bias_constant: f32,
    pub bias_slope: f32,
    pub normal_offset: f32,
    pub max_slope: f32,
    /// Bands of rows (`stages::shade::Band`): the band's first row in its dispatches' copy, every
    /// band's height (0: one band), the tile list's words per band and the number of bands.
    pub band_first_row: u32,
    pub band_rows: u32,
    pub tile_section_words: u32,
    pub bands: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuSample {
    pub light_from_world: [[f32; 4]; 4],
    pub position: [f32; 4],
    pub texel_angle: f32,
    pub depth_lin_a: f32,
    pub depth_lin_b: f32,
    pub layer: u32,
    pub array: u32,
    pub lattice: u32,
    /// 1: an orthographic map (the sun's): `position` is the unit direction towards the light
    /// (w = 0), `texel_angle` the texel's world size and linear depth `depth_lin_a·d + depth_lin_b`.
    pub orthographic: u32,
    /// 0, or 1 + the cube face (0..5: +x, −x, +y, −y, +z, −z) of a point light's map: the face
    /// looks up only the receivers whose direction from `position` has its axis dominant
    /// (docs/lights.md, "Cube maps for the point").
    pub cube_face: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuCamera {
    pub(crate) clip_from_world: [[f32; 4]; 4],
    pub(crate) eye: [f32; 4],
}

/// One slot of shadow_test's uniform sample blocks (kernels/shadow_test.wgsl), 2048 bytes so that
/// slots of one buffer start at 256-byte-aligned offsets.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuTestBlock {
    /// Lattice index of the block's sample j at `ks[j / 4][j % 4]`.
    pub ks: [[u32; 4]; 4],
    pub samples: [GpuSample; 16],
    pub(crate) pad: [[u32; 4]; 12],
}

/// One batch of the cull pass (kernels/cull.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct GpuCull {
    pub(crate) triangle_count: u32,
    /// Index capacity of one slot: the whole mesh, so no slot can overflow.
    pub(crate) slot_stride: u32,
    /// 0: the raster culls no face; 1: back faces; 2: front faces.
    pub(crate) cull_face: u32,
    /// Workgroups along x; z carries the rest of the triangles.
    pub(crate) groups_x: u32,
}

/// One dispatch chain of raster_compute (kernels/raster_compute.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct GpuRasterCompute {
    pub(crate) map_size: u32,
    pub(crate) triangle_count: u32,
    /// 0: no face is skipped; 1: back faces; 2: front faces.
    pub(crate) cull_face: u32,
    pub(crate) map_count: u32,
    pub(crate) large_capacity: u32,
    /// Always 0: the kernel XORs it into products so that none is fused into an fma.
    pub(crate) fence: u32,
    /// `requested`: this chain's first request in the level's list.
    pub(crate) first_request: u32,
    /// 1 under the GPU-steered loop: the chain's maps are its share of the level's requests.
    pub(crate) steered: u32,
}

/// One map of a raster_compute chain: its sample and the texel rectangle (inclusive) it is
/// rasterized in; texels outside keep the far value.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct GpuRasterJob {
    pub sample: u32,
    pub first_x: u32,
    pub first_y: u32,
    pub last_x: u32,
    pub last_y: u32,
    /// The cull pass's slot whose kept triangles the map draws, or `WHOLE_MESH`.
    pub kept_slot: u32,
    pub pad1: u32,
    pub pad2: u32,
}

impl GpuRasterJob {
    /// Sample `sample` over the whole map, or over a scissor `[x, y, w, h]`.
    pub fn new(sample: u32, map_size: u32, scissor: Option<[u32; 4]>) -> Self {
        let [x, y, w, h] = scissor.unwrap_or([0, 0, map_size, map_size]);
        Self {
            sample,
            first_x: x,
            first_y: y,
            last_x: x + w - 1,
            last_y: y + h - 1,
            kept_slot: Self::WHOLE_MESH,
            ..Default::default()
        }
    }
    /// `kept_slot` of a map that draws the whole mesh (the kernel's RASTER_WHOLE_MESH).
    pub const WHOLE_MESH: u32 = u32::MAX;
    pub fn whole(sample: u32, map_size: u32) -> Self {
        Self::new(sample, map_size, None)
    }
    /// [first_x, first_y, last_x, last_y].
    pub fn rect(&self) -> [i32; 4] {
        [
            self.first_x as i32,
            self.first_y as i32,
            self.last_x as i32,
            self.last_y as i32,
        ]
    }
}

/// The weights pass's rule (kernels/weights.wgsl): 0 level, 1 area, 2 Coons.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct GpuWeights {
    pub(crate) rule: u32,
    pub(crate) pad0: u32,
    pub(crate) pad1: u32,
    pub(crate) pad2: u32,
}

/// One map of hybrid_build: which raster layer merges into which store slot (docs/hybrid.md).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct GpuHybridBuild {
    pub(crate) levels: u32,
    /// Coarse texels per side: the raster size / 2^levels.
    pub(crate) coarse: u32,
    pub(crate) layer: u32,
    pub(crate) slot: u32,
    /// Pool words.
    pub(crate) capacity: u32,
    /// Merge tolerance in depth units (the setting's 16-bit units / 65535).
    pub(crate) eps: f32,
    pub(crate) pad0: u32,
    pub(crate) pad1: u32,
}

/// The hybrid store's allocation state: words used, the overflow flag, the last map's base and the
/// maps built since the last reset.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub(crate) struct GpuHybridControl {
    pub(crate) used: u32,
    pub(crate) overflow: u32,
    pub(crate) map_base: u32,
    pub(crate) built: u32,
}

/// Parameters of one adaptive level (shadow_test, reproject_count, neighbourhood, quad_count,
/// subdivide, compact).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuLevel {
    pub level: u32,
    pub max_level: u32,
    /// Active quads in this dispatch (a batch of the level's quads in dense mode).
    pub quad_count: u32,
    /// Index of the batch's first quad in the level's list.
    pub first_quad: u32,
    /// This level's threshold (`SPLIT_THRESHOLD`): a quad splits when its count exceeds it.
    pub split_threshold: u32,
    /// One of `SPLIT_*`.
    pub split_mode: u32,
    pub words_per_row: u32,
    pub flag_words_per_row: u32,
    pub item_capacity: u32,
    /// shadow_test: samples in the test list; with `requested`, the most it can hold (which block
    /// slots are dispatched).
    pub work_count: u32,
    pub dense_groups_x: u32,
    pub quad_capacity: u32,
    /// Unused: whether compact grows rectangles is which entry point the host dispatches
    /// (`main_rects`), not a uniform.
    pub pad0: u32,
    /// split_mode 3: this level's threshold as a share of the geometry pixels (docs/method.md §6).
    pub split_share: f32,
    /// shadow_test: 1 takes the test list's length from the append counter (GpuControl word 1).
    pub requested: u32,
    /// subdivide: the hysteresis margin in low-quality pixels of a quad the previous frame did not
    /// split (`adaptive:hold`, docs/reuse.md); 0 is no hysteresis.
    pub hold: u32,
}

/// `GpuLevel::split_mode` (`SPLIT_*` in kernels/shared/common.wgsl): a quad splits when its count
/// exceeds `split_threshold`, always, never, or when it exceeds `split_share` x the geometry pixels.
pub const SPLIT_THRESHOLD: u32 = 0;
pub const SPLIT_ALWAYS: u32 = 1;
pub const SPLIT_NEVER: u32 = 2;
pub const SPLIT_SHARE: u32 = 3;

/// Append counters shared by subdivide and compact (atomics in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuControl {
    pub next_quad_count: u32,
    pub new_sample_count: u32,
    pub overflow: u32,
    pub item_count: u32,
    /// Geometry pixels, counted by reproject_count at level 0 (the share criteria's denominator).
    pub geometry_pixels: u32,
    /// scope = local: probe items appended by compact for the next level.
    pub probe_count: u32,
    /// scope = local: shadow-map lookups of this level (shadow_test `list` and `probes`).
    pub lookups: u32,
    pub pad1: u32,
}

/// `GpuControl::overflow`'s bits (`OVERFLOW_*` in kernels/shared/common.wgsl): the quad list (256),
/// the (pixel, quad) item list and the probe list exceeded their capacity.
pub const OVERFLOW_QUADS: u32 = 1;
pub const OVERFLOW_ITEMS: u32 = 2;
pub const OVERFLOW_PROBES: u32 = 4;

/// A quad of the light's lattice: corner (i, j) and side in lattice steps.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Pod, Zeroable)]
pub struct GpuQuad {
    pub i: u32,
    pub j: u32,
    pub size: u32,
    pub parent: u32,
}

/// Parameters of the single-map filtering kernels (pcf, pcss, moments, blur, reconstruct).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuFilter {
    /// pcf: the kernel (box, bilinear, poisson, stratified, rotated); filtered: the statistic.
    pub(crate) kind: u32,
    /// pcf box/bilinear and pcss: taps per side; pcf disk kernels: tap count.
    pub(crate) taps: u32,
    /// pcss: blocker-search taps per side.
    pub(crate) blocker_taps: u32,
    /// pcf stratified: points in the disk drawn from; csm: Fourier order M.
    pub(crate) order: u32,
    /// pcf: filter radius in texels.
    pub(crate) radius: f32,
    /// pcf: seed 004's V = 1 - darkening · (shadowed taps); 0 averages the taps.
    pub(crate) darkening: f32,
    /// The area light's edge lengths (world units).
    pub(crate) light_u: f32,
    pub(crate) light_v: f32,
    /// esm and evsm exponents.
    pub(crate) c_pos: f32,
    pub(crate) c_neg: f32,
    /// vsm and evsm: light-bleeding reduction amount.
    pub(crate) bleed: f32,
    /// msm: moment bias α.
    pub(crate) moment_bias: f32,
    /// Moment planes (vec4 each).
    pub layers: u32,
    /// Box prefilter radius in texels.
    pub blur_radius: u32,
    /// pcss: largest search and filter half-width in texels.
    pub(crate) max_radius: f32,
    /// csm: receiver depth moved toward the light before the expansion is evaluated.
    pub(crate) depth_offset: f32,
}

/// The cascades kernel's uniform: the camera that picks a cascade by view depth, and the far end
/// of each cascade's slice of that depth (cascade i ends at `ends[i / 4][i % 4]`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuCascades {
    /// The camera's eye (w unused).
    pub(crate) eye: [f32; 4],
    /// The camera's unit forward: view depth is `dot(p − eye, forward)`.
    pub(crate) forward: [f32; 4],
    pub(crate) ends: [[f32; 4]; 2],
    pub(crate) count: u32,
    /// 0: one test per pixel (`hard`); 1: pcf's taps.
    pub(crate) filtering: u32,
    pub(crate) pad0: u32,
    pub(crate) pad1: u32,
}

/// A node of the environment rays' BVH: `count` = 0 for an inner node whose children are
/// `left_first` and `left_first + 1`; otherwise a leaf of `count` triangles from `left_first`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuBvhNode {
    pub(crate) min: [f32; 3],
    pub(crate) left_first: u32,
    pub(crate) max: [f32; 3],
    pub(crate) count: u32,
}

/// A triangle as the ray test reads it: one vertex and two edges (w unused).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuTriangle {
    pub(crate) v0: [f32; 4],
    pub(crate) e1: [f32; 4],
    pub(crate) e2: [f32; 4],
}

/// truth_trace's light and samples (kernels/truth_trace.wgsl): one uniform per dispatch.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuTruthParams {
    /// Rectangle, disk or sphere centre (w unused).
    pub(crate) center: [f32; 4],
    /// Rectangle: edge_u; sun: the unit direction towards it.
    pub(crate) edge_u: [f32; 4],
    /// Rectangle: edge_v.
    pub(crate) edge_v: [f32; 4],
    /// Rectangle and disk: the unit emission normal.
    pub(crate) light_normal: [f32; 4],
    /// 0 rectangle, 1 disk, 2 sun, 3 sphere (`certify::truth::TruthLight`).
    pub(crate) kind: u32,
    /// 0 continuous, 1 lattice, 2 point.
    pub(crate) mode: u32,
    pub(crate) m: u32,
    /// `1.0 / m as f32`, rounded as the CPU reference rounds it.
    pub(crate) inv_m: f32,
    /// Points in this dispatch.
    pub(crate) count: u32,
    pub(crate) seed_lo: u32,
    pub(crate) seed_hi: u32,
    pub(crate) ray_offset: f32,
    pub(crate) point_s: f32,
    pub(crate) point_t: f32,
    /// `1 − LIGHT_END_EPS` in f32.
    pub(crate) end_factor: f32,
    /// Disk and sphere: the radius; sun: tan(α/2).
    pub(crate) radius: f32,
    /// Sun: how far its rays go.
    pub(crate) reach: f32,
    /// The dispatch's first point (points are dispatched in chunks).
    pub(crate) first: u32,
    pub(crate) pad1: u32,
    pub(crate) pad2: u32,
}

/// A surface point truth_trace traces: the G-buffer's position and normal at `pixel`, whose
/// index seeds its samples as the reference's does.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuTruthPoint {
    pub(crate) position: [f32; 3],
    pub(crate) pixel: u32,
    pub(crate) normal: [f32; 3],
    pub(crate) pad: u32,
}

/// truth_trace's counts per point: samples that reach the light, rays traced, and rays whose
/// answer a tie in f32 decided (the CPU settles those in f64).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub(crate) struct GpuTruthCount {
    pub(crate) lit: u32,
    pub(crate) rays: u32,
    pub(crate) ties: u32,
    pub(crate) pad: u32,
}

/// A triangle as the watertight test reads it: its three vertices (w unused). The environment's
/// `GpuTriangle` stores two edges, rounded in f32, which neighbouring triangles do not share.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuTruthTriangle {
    pub(crate) v0: [f32; 4],
    pub(crate) v1: [f32; 4],
    pub(crate) v2: [f32; 4],
}

/// A directional light of the environment: xyz the unit direction towards it, w its power.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuEnvLight {
    pub(crate) direction: [f32; 4],
}

/// Parameters of the environment kernels (env_trace, env_count, env_split, env_shadowmaps, ssao).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuEnvParams {
    pub(crate) width: u32,
    pub(crate) height: u32,
    /// env_trace / env_shadowmaps: lights in the list; ssao: samples per pixel.
    pub(crate) light_count: u32,
    /// env_count / env_split: active cells this level.
    pub(crate) cell_count: u32,
    pub(crate) ray_offset: f32,
    pub(crate) t_max: f32,
    /// Cells per side of the finest level (the corner lattice has one more point per side).
    pub(crate) finest_width: u32,
    pub(crate) finest_height: u32,
    pub max_level: u32,
    pub(crate) p_m: u32,
    /// env_split: split when the children's powers differ by more than this factor.
    pub(crate) contrast: f32,
    /// env_split: cells below this share of the total power are never split.
    pub(crate) min_share: f32,
    pub(crate) total_power: f32,
    /// env_trace: 1 to multiply V by the ambient occlusion in `ao` (ssao combined).
    pub(crate) use_ao: u32,
    /// ssao: radius in world units.
    pub(crate) radius: f32,
    /// env_count: counts every count_stride-th pixel in x and y.
    pub(crate) count_stride: u32,
    /// env_trace: index of this dispatch's first light (lights go in chunks of ENV_TRACE_CHUNK).
    pub(crate) first_light: u32,
    /// env_trace: 1 on the last chunk, which writes V.
    pub(crate) final_chunk: u32,
    /// env_trace `vertex`: mesh vertices traced (the per-vertex variant).
    pub(crate) vertex_count: u32,
    pub(crate) pad1: u32,
}

/// A cell of the environment quadtree: corner (i, j) and side in finest-lattice steps.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Pod, Zeroable)]
pub struct GpuEnvCell {
    pub(crate) i: u32,
    pub(crate) j: u32,
    pub(crate) size: u32,
    pub(crate) level: u32,
}

/// Member offsets and size of a Rust GPU struct, for the layout test.
pub struct StructLayout {
    pub name: &'static str,
    pub size: usize,
    pub members: Vec<(&'static str, usize)>,
}

macro_rules! layout_of {
    ($t:ident { $($f:ident),* $(,)? }) => {
        StructLayout {
            name: stringify!($t),
            size: std::mem::size_of::<$t>(),
            members: vec![$((stringify!($f), std::mem::offset_of!($t, $f))),*],
        }
    };
}

/// Every struct shared with WGSL.
pub fn all_layouts() -> Vec<StructLayout> {
    vec![
        layout_of!(GpuFrame {
            width,
            height,
            map_size,
            flags,
            light_center,
            light_normal,
            bias_constant,
            bias_slope,
            normal_offset,
            max_slope,
            band_first_row,
            band_rows,
            tile_section_words,
            bands
        }),
        layout_of!(GpuSample {
            light_from_world,
            position,
            texel_angle,
            depth_lin_a,
            depth_lin_b,
            layer,
            array,
            lattice,
            orthographic,
            cube_face
        }),
        layout_of!(GpuCamera {
            clip_from_world,
            eye
        }),
        layout_of!(GpuTestBlock { ks, samples, pad }),
        layout_of!(GpuCull {
            triangle_count,
            slot_stride,
            cull_face,
            groups_x
        }),
        layout_of!(GpuWeights {
            rule,
            pad0,
            pad1,
            pad2
        }),
        layout_of!(GpuRasterCompute {
            map_size,
            triangle_count,
            cull_face,
            map_count,
            large_capacity,
            fence,
            first_request,
            steered
        }),
        layout_of!(GpuRasterJob {
            sample,
            first_x,
            first_y,
            last_x,
            last_y,
            kept_slot,
            pad1,
            pad2
        }),
        layout_of!(GpuLevel {
            level,
            max_level,
            quad_count,
            first_quad,
            split_threshold,
            split_mode,
            words_per_row,
            flag_words_per_row,
            item_capacity,
            work_count,
            dense_groups_x,
            quad_capacity,
            pad0,
            split_share,
            requested,
            hold
        }),
        layout_of!(GpuControl {
            next_quad_count,
            new_sample_count,
            overflow,
            item_count,
            geometry_pixels,
            probe_count,
            lookups,
            pad1
        }),
        layout_of!(GpuQuad { i, j, size, parent }),
        layout_of!(GpuHybridBuild {
            levels,
            coarse,
            layer,
            slot,
            capacity,
            eps,
            pad0,
            pad1
        }),
        layout_of!(GpuHybridControl {
            used,
            overflow,
            map_base,
            built
        }),
        layout_of!(GpuFilter {
            kind,
            taps,
            blocker_taps,
            order,
            radius,
            darkening,
            light_u,
            light_v,
            c_pos,
            c_neg,
            bleed,
            moment_bias,
            layers,
            blur_radius,
            max_radius,
            depth_offset
        }),
        layout_of!(GpuCascades {
            eye,
            forward,
            ends,
            count,
            filtering,
            pad0,
            pad1
        }),
        layout_of!(GpuBvhNode {
            min,
            left_first,
            max,
            count
        }),
        layout_of!(GpuTriangle { v0, e1, e2 }),
        layout_of!(GpuEnvLight { direction }),
        layout_of!(GpuEnvParams {
            width,
            height,
            light_count,
            cell_count,
            ray_offset,
            t_max,
            finest_width,
            finest_height,
            max_level,
            p_m,
            contrast,
            min_share,
            total_power,
            use_ao,
            radius,
            count_stride,
            first_light,
            final_chunk,
            vertex_count,
            pad1
        }),
        layout_of!(GpuEnvCell { i, j, size, level }),
        layout_of!(GpuTruthParams {
            center,
            edge_u,
            edge_v,
            light_normal,
            kind,
            mode,
            m,
            inv_m,
            count,
            seed_lo,
            seed_hi,
            ray_offset,
            point_s,
            point_t,
            end_factor,
            radius,
            reach,
            first,
            pad1,
            pad2
        }),
        layout_of!(GpuTruthPoint {
            position,
            pixel,
            normal,
            pad
        }),
        layout_of!(GpuTruthCount {
            lit,
            rays,
            ties,
            pad
        }),
        layout_of!(GpuTruthTriangle { v0, v1, v2 }),
    ]
}
